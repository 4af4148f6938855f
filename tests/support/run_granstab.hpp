#pragma once
// The built granstab binary run from a test (tests/support, the one helper for
// it): in a fresh empty directory, with stdout and stderr captured beside it,
// so that a test sees exactly which files a command writes.
#include <filesystem>
#include <string>
#include <vector>

namespace granstab::testing {

namespace fs = std::filesystem;

// The path of the built granstab executable.
const char* granstab_exe();

std::string slurp(const fs::path& p);
void spit(const fs::path& p, const std::string& text);
// s in single quotes, for a shell command line (s must not contain a single
// quote).
std::string quoted(const std::string& s);

// The number after "key": in a flat JSON text (NaN when absent or null).
double json_number(const std::string& json, const std::string& key);

struct CommandResult {
  int exit_code;  // -1 when the command did not exit normally
  std::string out, err;
};

class Workdir {
 public:
  // A new directory TMP/granstab-TAG-RANDOM/work; removed with everything in it
  // by the destructor.
  explicit Workdir(const std::string& tag);
  ~Workdir();
  Workdir(const Workdir&) = delete;
  Workdir& operator=(const Workdir&) = delete;

  const fs::path& path() const { return work_; }
  // The directory holding path() and the captured streams: a place for a test's own input files,
  // which are then not among the files the command wrote.
  const fs::path& root() const { return root_; }
  fs::path operator/(const std::string& name) const { return work_ / name; }

  // Runs `granstab ARGS` (ARGS as on a shell command line) in path() with
  // OMP_NUM_THREADS=1.
  CommandResult run(const std::string& args) const;
  // Every file and directory under path(), relative to it.
  std::vector<std::string> files() const;

 private:
  fs::path root_, work_;
};

}  // namespace granstab::testing
