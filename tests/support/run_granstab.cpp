#include "run_granstab.hpp"

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>

namespace granstab::testing {

const char* granstab_exe() { return GRANSTAB_EXE; }

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void spit(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

std::string quoted(const std::string& s) {
  std::string q;  // built by push_back: GCC 12 warns falsely (-Wrestrict) on "'"
                  // + s + "'"
  q.reserve(s.size() + 2);
  q.push_back('\'');
  q.append(s);
  q.push_back('\'');
  return q;
}

Workdir::Workdir(const std::string& tag) {
  root_ = fs::temp_directory_path() /
          ("granstab-" + tag + "-" + std::to_string(std::random_device{}()));
  work_ = root_ / "work";
  fs::create_directories(work_);
}

Workdir::~Workdir() {
  std::error_code ignored;
  fs::remove_all(root_, ignored);
}

CommandResult Workdir::run(const std::string& args) const {
  std::ostringstream command;  // (a stream: GCC 12 warns falsely on long string sums)
  command << "cd " << quoted(work_.string()) << " && OMP_NUM_THREADS=1 " << quoted(granstab_exe())
          << ' ' << args << " > " << quoted((root_ / "out").string()) << " 2> "
          << quoted((root_ / "err").string());
  const int status = std::system(command.str().c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(root_ / "out"), slurp(root_ / "err")};
}

std::vector<std::string> Workdir::files() const {
  std::vector<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(work_)) {
    names.push_back(fs::relative(e.path(), work_).string());
  }
  return names;
}

double json_number(const std::string& json, const std::string& key) {
  const std::string tag = "\"" + key + "\": ";
  const std::size_t at = json.find(tag);
  if (at == std::string::npos) return std::nan("");
  const char* begin = json.c_str() + at + tag.size();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  return end == begin ? std::nan("") : v;
}

}  // namespace granstab::testing
