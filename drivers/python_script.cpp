#include "python_script.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

extern char** environ;

namespace granstab::cli {
namespace {

// Runs argv[0] with the given arguments; returns its exit status (-1 if it could not start).
int run_program(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

void run_python_script(const std::string& python, const std::string& script,
                       const std::vector<std::string>& args) {
  const std::filesystem::path path = std::filesystem::path(GRANSTAB_SOURCE_DIR) / script;
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error(path.string() + ": script not found (source tree moved?)");
  ::setenv("MPLBACKEND", "Agg", 1);
  const int probe = run_program({python, "-c", "import matplotlib, numpy"});
  if (probe < 0) throw std::runtime_error(python + ": cannot run this Python interpreter");
  if (probe != 0)
    throw std::runtime_error(python +
                             " cannot import matplotlib and numpy: install them with "
                             "`apt-get install python3-matplotlib python3-numpy` "
                             "(scripts/install-deps.sh)");
  std::vector<std::string> command{python, path.string()};
  command.insert(command.end(), args.begin(), args.end());
  const int status = run_program(command);
  if (status != 0)
    throw std::runtime_error(path.string() + " failed (exit status " + std::to_string(status) +
                             ")");
}

}  // namespace granstab::cli
