// granstab compare SAMPLE --dq X: the cross-check of SPEC §5. Both methods run from the sample's
// equilibrium with the same delta q (drivers/crosscheck.hpp); this file parses, calls, writes
// every output atomically once everything is computed, and prints a verdict table. The dynamic
// half writes checkpoints like the other protocol commands (--set checkpoint.every_steps=N ...)
// and `granstab resume` continues it (docs/reliability.md).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "common/atomic_file.hpp"
#include "common/io/configuration_file.hpp"
#include "common/run_config.hpp"
#include "crosscheck.hpp"
#include "stability_probe.hpp"
#include "static_start.hpp"
#include "dynamic/protocols/settings.hpp"
#include "resumable.hpp"

namespace granstab::cli {
namespace {

struct CompareCommandOptions {
  std::string sample;
  std::string out = "compare-out";
  std::vector<std::string> overrides;  // --set: [engine], [checkpoint] and [sanity] settings
  crosscheck::CrosscheckOptions run;
  StaticStartOptions start;  // --mu, --kt-ratio, --set material.*, --polish, ...
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
  row("largest dynamic eps2 step below q1", "%.3e at q = %.6g (%.3g x mean)",
      c.max_dynamic_step_below_q1, c.q_of_max_dynamic_step,
      c.max_dynamic_step_below_q1 / c.mean_dynamic_step_below_q1);
  row("dynamic eps2 jump after q1", "%.3e at q = %.6g%s", c.dynamic_jump_after_q1, c.q_of_jump,
      c.jump_reached_equilibrium ? "" : " (no equilibrium)");
  if (!r.probes.empty()) {
    std::string list;
    for (const crosscheck::ProbeResult& p : r.probes) {
      std::snprintf(buf, sizeof buf, "%s%.4g %s (%.2g)", list.empty() ? "" : ", ", p.q,
                    p.stable ? "stays" : "moves", std::abs(p.final_d_eps2) / p.bound_eps2);
      list += buf;
    }
    row("static states probed (|d eps2| / bound)", "%s", list.c_str());
    row("static states stable up to q", "%.6g", crosscheck::stable_up_to(r.probes));
  }
  row("seconds static / dynamic", "%.3g / %.3g", r.static_seconds, r.dynamic_seconds);
  const bool agree = c.n_steps_compared > 0 && c.max_diff_over_bound_eps2 <= 1.0;
  const bool agree_before =
      c.n_compared_before_sliding > 0 && c.max_diff_over_bound_eps2_before_sliding <= 1.0;
  // Which path strained more where they differ most (the sign is not the same on every sample).
  const char* more =
      c.diff_eps2_at_max > 0.0 ? "the dynamic path strains more" : "the static path strains more";
  if (c.n_steps_compared == 0)
    std::printf("verdict: nothing to compare (no dynamic equilibrium below q1)\n");
  else if (agree)
    std::printf("verdict: static and dynamic agree below q1 within the SPEC 3.1 tolerances\n");
  else if (agree_before)
    std::printf(
        "verdict: static and dynamic agree within the SPEC 3.1 tolerances until the first "
        "sliding contact; beyond, %s (see user guide)\n",
        more);
  else
    std::printf(
        "verdict: static and dynamic differ by more than the SPEC 3.1 tolerances allow, "
        "%s (see compare.json and the user guide)\n",
        more);
  std::printf("outputs in %s\n", dir.string().c_str());
  std::fflush(stdout);
}

// The files compare writes into its output directory, in this order.
constexpr const char* output_names[] = {"static_curve.csv", "dynamic_curve.csv", "matched.csv",
                                        "disks_at_q1.csv",  "network_at_q1.csv", "mode.csv",
                                        "compare.json"};

// Declares compare's options on cmd: the subcommand, or the parser a resume runs on the stored
// arguments.
void add_options(CLI::App& cmd, CompareCommandOptions& o) {
  cmd.add_option("SAMPLE", o.sample, "equilibrium configuration file (docs/file-format.md)")
      ->required();
  cmd.add_option("--dq", o.run.dq, "delta q of both methods")
      ->required()
      ->check(CLI::PositiveNumber);
  cmd.add_option("--q-max", o.run.q_max,
                 "highest q of both runs (default: static to q1, dynamic a few steps beyond)")
      ->check(CLI::PositiveNumber);
  cmd.add_option("--steps-after-q1", o.run.steps_after_q1,
                 "dynamic increments beyond q1 when --q-max is not given")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd.add_option("--out", o.out, "output directory")->capture_default_str();
  add_md_wait_options(cmd, o.run.equilibration, o.run.epsilon_2_max);
  cmd.add_option("--dynamic-substeps", o.run.dynamic_substeps,
                 "dynamic run: each delta q as N stress steps of delta q / N (a staircase "
                 "ramp), states recorded at multiples of delta q only")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd.add_option("--static-substeps", o.run.static_substeps,
                 "static run: steps of delta q / N, states compared at multiples of delta q")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd.add_option("--probe-states", o.run.probe.states,
                 "probe K static states (q = k q1 / K, k = 1..K) with the dynamic engine: SIC "
                 "hold and random perturbations (granstab probe; issue #6)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd.add_option("--probe-f0", o.run.probe.f0, "perturbation forces of the probe (units of aP)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd.add_option("--probe-draws", o.run.probe.draws, "perturbation draws of the probe")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  add_hill_option(cmd, o.run.statics.hill_every);
  add_step_control_option(cmd, o.run.statics);
  cmd.add_option("--set", o.overrides,
                 "key=value: the dynamic half's engine.dt_fraction, engine.skin, checkpoint.path "
                 "(default OUT/compare.checkpoint), checkpoint.every_steps, "
                 "checkpoint.every_seconds, sanity.* (as in the settings of the other commands, "
                 "docs/reliability.md); material.KEY=VALUE sets the biaxial stage's material "
                 "for both methods (KEY: k_n, k_t, mu, zeta, mu_wall)");
  add_static_start_options(cmd, o.start, false);
}

CompareCommandOptions parse_arguments(const std::vector<std::string>& arguments) {
  CompareCommandOptions o;
  CLI::App parser{"granstab compare", "compare"};
  add_options(parser, o);
  std::vector<std::string> reversed(arguments.rbegin(), arguments.rend());  // CLI11's order
  parser.parse(reversed);
  split_material_settings(o.overrides, o.start);
  return o;
}

// Fingerprint of everything the static half gives the outputs and the dynamic half: a resume
// re-runs the static half and refuses to go on if it does not give the same bits.
std::string static_fingerprint(const crosscheck::CrosscheckResult& r, double q_end) {
  std::string text = crosscheck::static_curve_csv(r.statics) +
                     crosscheck::disks_at_q1_csv(r.statics) +
                     crosscheck::network_at_q1_csv(r.statics) + crosscheck::mode_csv(r.statics);
  for (const double v :
       {r.statics.q1, r.statics.q1_bracket[0], r.statics.q1_bracket[1], r.rigid.q_max, q_end}) {
    text += crosscheck::json_number(v) + ' ';
  }
  text += std::string(statics::criterion_name(r.statics.criterion)) + r.statics.detail +
          r.rigid.status + std::to_string(r.statics.steps) + ' ' +
          std::to_string(r.statics.sliding_at_q1.size());
  return std::to_string(protocols::fnv1a64(text));
}

}  // namespace

void run_compare(const protocols::Invocation& invocation, const protocols::Checkpoint* checkpoint) {
  CompareCommandOptions o = parse_arguments(invocation.arguments);
  const std::filesystem::path dir = o.out;
  RunConfig rc = invocation.settings_config();  // the --set overrides, and a resume's
  o.run.engine = protocols::read_engine_options(rc);
  const protocols::GuardSettings guard_settings =
      protocols::read_guard_settings(rc, dir / "compare.checkpoint");
  rc.finish();
  std::vector<std::filesystem::path> outputs{guard_settings.checkpoint};
  for (const char* name : output_names) outputs.push_back(dir / name);
  protocols::remove_stale_temporaries(outputs);
  // Validated before any output exists: a refused start leaves no file behind.
  const StaticStart start = read_static_start(o.sample, o.start, crosscheck::require_biaxial_start);
  const Configuration& sample = start.config;
  o.run.statics.on_progress =
      static_progress("compare (static half)", !o.start.quiet, o.run.q_max, "--q-max");
  const std::string input_checksum = protocols::file_checksum(o.sample);
  if (checkpoint) require_same_input(*checkpoint, o.sample, input_checksum);

  // The static half is not checkpointed: a resume runs it again (it is deterministic, and storing
  // it would need a format for the whole StabilityResult) and checks it gives the same bits; that
  // repeats 0.5 to 1.1 times the dynamic half's work on the N = 100 sample (docs/reliability.md).
  crosscheck::CrosscheckResult r = crosscheck::run_static_half(sample, o.run);
  const double q_end = crosscheck::dynamic_q_end(r, o.run);
  const std::string static_checksum = static_fingerprint(r, q_end);
  if (checkpoint && checkpoint->text("compare.static_checksum") != static_checksum) {
    throw std::runtime_error(checkpoint->source_name() +
                             ": the static half, run again, differs from the one before the "
                             "checkpoint (another build or thread count?); cannot resume");
  }

  protocols::LoopControl control;
  Configuration from = r.start;
  double seconds_before = 0.0;
  if (checkpoint) {
    from = checkpoint->configuration("engine");
    r.dynamic = crosscheck::parse_dynamic_run_state(checkpoint->text("compare.dynamic"));
    seconds_before = checkpoint->number("run.wall_seconds");  // of the dynamic half
    control.cursor = protocols::get_cursor(*checkpoint);
    control.resume = true;
  }
  protocols::RunGuard guard(guard_settings, "compare");
  const auto started = std::chrono::steady_clock::now();
  const auto dynamic_seconds = [&] {
    return seconds_before +
           std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  };
  const auto build = [&](const Engine& e, const protocols::Cursor& cursor) {
    protocols::Checkpoint c =
        checkpoint_head(invocation, e, cursor, input_checksum, dynamic_seconds());
    c.set("compare.static_checksum", static_checksum);
    c.set("compare.dynamic", crosscheck::dynamic_run_state(r.dynamic));
    return c;
  };
  guard.on_write([&] {
    const auto parent = guard_settings.checkpoint.parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
  });
  control.hooks = guard_hooks(guard, build);
  crosscheck::run_dynamic(from, o.run, q_end, r.dynamic, control);
  r.dynamic_seconds = dynamic_seconds();
  crosscheck::compare_halves(r, o.run);
  // After the dynamic half (not checkpointed: deterministic, seconds on the shipped sample).
  const auto probe_start = std::chrono::steady_clock::now();
  r.probes = crosscheck::probe_static_states(r, o.run);
  r.probe_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - probe_start).count();

  // Everything is formatted before the first file is written: an error leaves no partial output.
  const crosscheck::JsonContext context{o.sample, o.run.dq, o.run.q_max,
                                        static_start_json(start, "  ") + ",\n"};
  const std::string texts[] = {
      crosscheck::static_curve_csv(r.statics),    crosscheck::dynamic_curve_csv(r.dynamic),
      crosscheck::matched_csv(r.comparison),      crosscheck::disks_at_q1_csv(r.statics),
      crosscheck::network_at_q1_csv(r.statics),   crosscheck::mode_csv(r.statics),
      crosscheck::compare_json(context, o.run, r)};
  std::filesystem::create_directories(dir);
  for (std::size_t k = 0; k < std::size(output_names); ++k) {
    write_file_atomically(dir / output_names[k], texts[k]);
  }
  guard.finish();
  print_verdict(r, dir);
}

void add_compare_command(CLI::App& app) {
  auto o = std::make_shared<CompareCommandOptions>();
  auto* cmd = app.add_subcommand(
      "compare",
      "Cross-check (SPEC §5): static stepping and dynamic SIC from the same equilibrium sample "
      "with the same delta q; writes DIR/static_curve.csv, dynamic_curve.csv, compare.json and "
      "the files `granstab plot DIR` draws");
  add_options(*cmd, *o);
  cmd->callback([o] {
    // The arguments as given, kept in checkpoints and parsed again by run_compare and a resume.
    const std::vector<std::string>& line = command_line();
    const auto at = std::find(line.begin(), line.end(), "compare");
    if (at == line.end()) throw std::logic_error("compare: not on the command line");
    // The material.* settings are the static start's (parsed again by run_compare), not the
    // dynamic half's [engine] / [checkpoint] / [sanity] settings.
    std::vector<std::string> settings = o->overrides;
    StaticStartOptions ignored;
    split_material_settings(settings, ignored);
    run_compare(protocols::Invocation::from_arguments("compare", {at + 1, line.end()}, settings),
                nullptr);
  });
}

}  // namespace granstab::cli
