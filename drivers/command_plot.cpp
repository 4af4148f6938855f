// granstab plot DIR: redraws the pictures of a `granstab compare` or `granstab sic` output
// directory from its CSV and JSON files, by running scripts/plot/plot_compare.py or plot_sic.py
// with /usr/bin/python3 and the Agg backend (DEPS.md #6: the python3 on PATH may lack matplotlib).
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
  std::string reference;  // sic: a pure dynamic run drawn beneath
};

void run_plot(const PlotOptions& o) {
  const std::filesystem::path dir = o.dir;
  if (std::filesystem::is_regular_file(dir / "sic.json")) {
    std::vector<std::string> args{dir.string()};
    if (!o.reference.empty()) args.push_back(o.reference);
    run_python_script(o.python, "scripts/plot/plot_sic.py", args);
    return;
  }
  if (!std::filesystem::is_regular_file(dir / "compare.json"))
    throw std::runtime_error(dir.string() +
                             ": no compare.json or sic.json (run `granstab compare SAMPLE --dq X "
                             "--out DIR` or `granstab sic SAMPLE --dq X --out DIR` first)");
  run_python_script(o.python, "scripts/plot/plot_compare.py", {dir.string()});
}

}  // namespace

void add_plot_command(CLI::App& app) {
  auto o = std::make_shared<PlotOptions>();
  auto* cmd = app.add_subcommand(
      "plot",
      "Draws the pictures of a `granstab compare` directory (PNG and SVG): curves with q1, "
      "the sample at q1 with force chains, sliding contacts and the unstable mode; of a "
      "`granstab sic` directory: the curve coloured by method, the jumps, the force networks "
      "around the largest rearrangements");
  cmd->add_option("DIR", o->dir, "output directory of granstab compare or sic")->required();
  cmd->add_option("--reference", o->reference,
                  "sic: the output directory of a pure dynamic run, drawn beneath the curve");
  cmd->add_option("--python", o->python, "Python interpreter with matplotlib")
      ->capture_default_str();
  cmd->callback([o] { run_plot(*o); });
}

}  // namespace granstab::cli
