// granstab compare SAMPLE --dq X: the cross-check of SPEC §5. Both methods run from the sample's
// equilibrium with the same delta q (drivers/crosscheck.hpp); this file parses, calls, writes
// every output atomically once everything is computed, and prints a verdict table.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "common/atomic_file.hpp"
#include "common/io/configuration_file.hpp"
#include "crosscheck.hpp"

namespace granstab::cli {
namespace {

struct CompareCommandOptions {
  std::string sample;
  std::string out = "compare-out";
  crosscheck::CrosscheckOptions run;
};

void print_verdict(const crosscheck::CrosscheckResult& r, const std::filesystem::path& dir) {
  const crosscheck::Comparison& c = r.comparison;
  char buf[512];
  std::printf("%-38s %s\n", "quantity", "value");
  const auto row = [&](const char* name, const char* fmt, auto... v) {
    std::snprintf(buf, sizeof buf, fmt, v...);
    std::printf("%-38s %s\n", name, buf);
  };
  row("mu (both methods)", "%.6g", r.mu);
  if (r.statics.criterion == statics::Criterion::none)
    row("q1 (static)", "> %.9g (stable up to the last state)", r.statics.q1);
  else
    row("q1 (static)", "%.9g in [%.9g, %.9g]", r.statics.q1, r.statics.q1_bracket[0],
        r.statics.q1_bracket[1]);
  row("criterion", "%s", statics::criterion_name(r.statics.criterion));
  row("q_max rigid limit (SPEC 4.5)", "%.6g (%s)", r.rigid.q_max, r.rigid.status.c_str());
  row("states compared below q1", "%d (%d interpolated)", c.n_steps_compared, c.n_interpolated);
  row("max |d eps2| below q1", "%.3e", c.max_abs_diff_eps2);
  row("max |d eps2| / |eps2|", "%.3e", c.max_rel_diff_eps2);
  row("max |d eps_v| below q1", "%.3e", c.max_abs_diff_epsv);
  row("max |d eps2| / tolerance bound", "%.3g", c.max_diff_over_bound_eps2);
  row("first sliding contact (static) at q", "%.6g", c.q_first_static_sliding);
  row("max |d eps2| / bound before it", "%.3g (%d states)",
      c.max_diff_over_bound_eps2_before_sliding, c.n_compared_before_sliding);
  row("mean dynamic eps2 step below q1", "%.3e", c.mean_dynamic_step_below_q1);
  row("dynamic eps2 jump after q1", "%.3e at q = %.6g%s", c.dynamic_jump_after_q1, c.q_of_jump,
      c.jump_reached_equilibrium ? "" : " (no equilibrium)");
  row("seconds static / dynamic", "%.3g / %.3g", r.static_seconds, r.dynamic_seconds);
  const bool agree = c.n_steps_compared > 0 && c.max_diff_over_bound_eps2 <= 1.0;
  const bool agree_before =
      c.n_compared_before_sliding > 0 && c.max_diff_over_bound_eps2_before_sliding <= 1.0;
  std::printf("verdict: %s\n",
              c.n_steps_compared == 0
                  ? "nothing to compare (no dynamic equilibrium below q1)"
              : agree ? "static and dynamic agree below q1 within the SPEC 3.1 tolerances"
              : agree_before
                  ? "static and dynamic agree within the SPEC 3.1 tolerances until the first "
                    "sliding contact; beyond, the dynamic path slips more (see user guide)"
                  : "static and dynamic differ by more than the SPEC 3.1 tolerances allow "
                    "(see compare.json and the user guide)");
  std::printf("outputs in %s\n", dir.string().c_str());
  std::fflush(stdout);
}

void run_compare(const CompareCommandOptions& o) {
  const Configuration sample = read_configuration(o.sample);
  const crosscheck::CrosscheckResult r = crosscheck::run_crosscheck(sample, o.run);
  // Everything is formatted before the first file is written: an error leaves no partial output.
  const crosscheck::JsonContext context{o.sample, o.run.dq, o.run.q_max};
  const std::vector<std::pair<std::string, std::string>> files{
      {"static_curve.csv", crosscheck::static_curve_csv(r.statics)},
      {"dynamic_curve.csv", crosscheck::dynamic_curve_csv(r.dynamic)},
      {"matched.csv", crosscheck::matched_csv(r.comparison)},
      {"disks_at_q1.csv", crosscheck::disks_at_q1_csv(r.statics)},
      {"network_at_q1.csv", crosscheck::network_at_q1_csv(r.statics)},
      {"mode.csv", crosscheck::mode_csv(r.statics)},
      {"compare.json", crosscheck::compare_json(context, o.run, r)},
  };
  const std::filesystem::path dir = o.out;
  std::filesystem::create_directories(dir);
  for (const auto& [name, text] : files) write_file_atomically(dir / name, text);
  print_verdict(r, dir);
}

}  // namespace

void add_compare_command(CLI::App& app) {
  auto o = std::make_shared<CompareCommandOptions>();
  auto* cmd = app.add_subcommand(
      "compare",
      "Cross-check (SPEC §5): static stepping and dynamic SIC from the same equilibrium sample "
      "with the same delta q; writes DIR/static_curve.csv, dynamic_curve.csv, compare.json and "
      "the files `granstab plot DIR` draws");
  cmd->add_option("SAMPLE", o->sample, "equilibrium configuration file (docs/file-format.md)")
      ->required();
  cmd->add_option("--dq", o->run.dq, "delta q of both methods")
      ->required()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--q-max", o->run.q_max,
                  "highest q of both runs (default: static to q1, dynamic a few steps beyond)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--steps-after-q1", o->run.steps_after_q1,
                  "dynamic increments beyond q1 when --q-max is not given")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--mu", o->run.mu,
                  "friction of the biaxial stage, both methods (default: the sample's material.mu)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--out", o->out, "output directory")->capture_default_str();
  cmd->add_option("--force-tolerance", o->run.equilibration.tolerances.force,
                  "dynamic SPEC 3.1 net-force tolerance (units of aP)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--torque-tolerance", o->run.equilibration.tolerances.torque,
                  "dynamic SPEC 3.1 net-torque tolerance (units of a^2 P)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--stress-tolerance", o->run.equilibration.tolerances.stress,
                  "dynamic SPEC 3.1 relative stress tolerance")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--max-steps-per-increment", o->run.equilibration.max_steps,
                  "MD steps allowed to reach equilibrium after one increment")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--epsilon-2-max", o->run.epsilon_2_max,
                  "the dynamic run stops when epsilon_2 exceeds this (the sample flows)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--dynamic-substeps", o->run.dynamic_substeps,
                  "dynamic run: each delta q as N stress steps of delta q / N (a staircase "
                  "ramp), states recorded at multiples of delta q only")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--static-substeps", o->run.static_substeps,
                  "static run: steps of delta q / N, states compared at multiples of delta q")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_flag("!--no-hill", o->run.statics.hill,
                "skip the Hill indicator of the static states (faster)");
  cmd->callback([o] { run_compare(*o); });
}

}  // namespace granstab::cli
