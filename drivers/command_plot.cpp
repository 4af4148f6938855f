// granstab plot DIR: redraws the pictures of a `granstab compare` output directory from its CSV and
// JSON files, by running scripts/plot/plot_compare.py with /usr/bin/python3 and the Agg backend
// (DEPS.md #6: the python3 on PATH may lack matplotlib).
#include <CLI/CLI.hpp>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "python_script.hpp"

namespace granstab::cli {
namespace {

struct PlotOptions {
  std::string dir;
  std::string python = "/usr/bin/python3";
};

void run_plot(const PlotOptions& o) {
  const std::filesystem::path dir = o.dir;
  if (!std::filesystem::is_regular_file(dir / "compare.json"))
    throw std::runtime_error(dir.string() +
                             ": no compare.json (run `granstab compare SAMPLE --dq X --out DIR` "
                             "first)");
  run_python_script(o.python, "scripts/plot/plot_compare.py", {dir.string()});
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
