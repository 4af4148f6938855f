// granstab plot DIR: redraws the pictures of a `granstab compare` output directory from its CSV and
// JSON files, by running scripts/plot/plot_compare.py with /usr/bin/python3 and the Agg backend
// (DEPS.md #6: the python3 on PATH may lack matplotlib).
#include <CLI/CLI.hpp>
#include <spawn.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"

extern char** environ;

namespace granstab::cli {
namespace {

struct PlotOptions {
  std::string dir;
  std::string python = "/usr/bin/python3";
};

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

void run_plot(const PlotOptions& o) {
  const std::filesystem::path dir = o.dir;
  if (!std::filesystem::is_regular_file(dir / "compare.json"))
    throw std::runtime_error(dir.string() +
                             ": no compare.json (run `granstab compare SAMPLE --dq X --out DIR` "
                             "first)");
  const std::filesystem::path script =
      std::filesystem::path(GRANSTAB_SOURCE_DIR) / "scripts" / "plot" / "plot_compare.py";
  if (!std::filesystem::is_regular_file(script))
    throw std::runtime_error(script.string() + ": plotting script not found (source tree moved?)");
  ::setenv("MPLBACKEND", "Agg", 1);
  const int probe = run_program({o.python, "-c", "import matplotlib"});
  if (probe < 0) throw std::runtime_error(o.python + ": cannot run this Python interpreter");
  if (probe != 0)
    throw std::runtime_error(o.python +
                             " cannot import matplotlib: install it with "
                             "`apt-get install python3-matplotlib` (scripts/install-deps.sh)");
  const int status = run_program({o.python, script.string(), dir.string()});
  if (status != 0)
    throw std::runtime_error(script.string() + " failed (exit status " + std::to_string(status) +
                             ")");
}

}  // namespace

void add_plot_command(CLI::App& app) {
  auto o = std::make_shared<PlotOptions>();
  auto* cmd = app.add_subcommand(
      "plot",
      "Draws the pictures of a `granstab compare` directory (PNG and SVG): curves with q1, "
      "the sample at q1 with force chains, sliding contacts and the unstable mode");
  cmd->add_option("DIR", o->dir, "output directory of granstab compare")->required();
  cmd->add_option("--python", o->python, "Python interpreter with matplotlib")
      ->capture_default_str();
  cmd->callback([o] { run_plot(*o); });
}

}  // namespace granstab::cli
