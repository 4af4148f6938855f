#pragma once
// Runs the built granstab binary in a fresh empty directory (as tests/drivers does), so that
// a test sees exactly which files a command writes.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace granstab::testing {

namespace fs = std::filesystem;

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void spit(const fs::path& p, const std::string& text) {
  std::ofstream out(p);
  out << text;
}

struct CommandResult {
  int exit_code;
  std::string out, err;
};

class Workdir {
 public:
  explicit Workdir(const std::string& tag) {
    root_ = fs::temp_directory_path() /
            ("granstab-" + tag + "-" + std::to_string(std::random_device{}()));
    work_ = root_ / "work";
    fs::create_directories(work_);
  }
  ~Workdir() { fs::remove_all(root_); }
  Workdir(const Workdir&) = delete;
  Workdir& operator=(const Workdir&) = delete;

  const fs::path& path() const { return work_; }
  fs::path operator/(const std::string& name) const { return work_ / name; }

  CommandResult run(const std::string& args) const {
    const std::string command = "cd '" + work_.string() + "' && OMP_NUM_THREADS=1 '" +
                                GRANSTAB_EXE + "' " + args + " > '" + (root_ / "out").string() +
                                "' 2> '" + (root_ / "err").string() + "'";
    const int status = std::system(command.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(root_ / "out"),
            slurp(root_ / "err")};
  }

  std::vector<std::string> files() const {
    std::vector<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(work_)) {
      names.push_back(fs::relative(e.path(), work_).string());
    }
    return names;
  }

 private:
  fs::path root_, work_;
};

}  // namespace granstab::testing
