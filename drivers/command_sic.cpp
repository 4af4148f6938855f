// granstab sic SAMPLE --dq X [--hybrid]: the stress-increment biaxial test (SPEC §3.3) from an
// equilibrium sample given on the command line, either every increment by MD or, with --hybrid,
// by static stepping inside the stability intervals and MD across the rearrangements (issue #24,
// drivers/hybrid_sic.hpp). Writes DIR/sic_curve.csv, DIR/sic.json and the force networks before
// and after the largest rearrangements, all atomically once the run has ended; DIR/sic.checkpoint
// at every MD equilibrium, from which the same command line continues after a kill.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "common/atomic_file.hpp"
#include "common/io/json_text.hpp"
#include "common/progress.hpp"
#include "common/run_config.hpp"
#include "crosscheck.hpp"
#include "dynamic/protocols/checkpoint.hpp"
#include "dynamic/protocols/run_guard.hpp"
#include "dynamic/protocols/settings.hpp"
#include "hybrid_sic.hpp"
#include "python_script.hpp"
#include "resumable.hpp"
#include "static_start.hpp"

namespace granstab::cli {
namespace {

struct SicCommandOptions {
  std::string sample;
  std::string out = "sic-out";
  std::vector<std::string> overrides;  // --set engine.* and material.*
  hybrid::SicOptions run;
  StaticStartOptions start;
  // The static step floor. Default dq / 1000, not q1's 1e-7: past the last stable state the MD
  // takes the sample to the next increment anyway, so locating each loss of stability more
  // finely changes only where a static interval ends, at ~1 attempt per halving.
  std::optional<double> dq_min;
  int pictures = 3;  // force networks of this many largest rearrangements
  bool plot = false;
};

std::string sic_curve_csv(const hybrid::SicResult& r) {
  std::ostringstream s;
  s << "state,method,interval,q_target,q,epsilon_1,epsilon_2,epsilon_v,n_sliding,md_steps,"
       "on_grid,reached,interpolated\n";
  for (std::size_t k = 0; k < r.curve.size(); ++k) {
    const hybrid::SicPoint& p = r.curve[k];
    s << k << ',' << hybrid::method_name(p.method) << ',' << p.interval << ','
      << json_number(p.q_target) << ',' << json_number(p.q) << ',' << json_number(p.eps1) << ','
      << json_number(p.eps2) << ',' << json_number(p.epsv) << ',' << p.n_sliding << ','
      << p.md_steps << ',' << (p.on_grid ? 1 : 0) << ',' << (p.reached ? 1 : 0) << ','
      << (p.interpolated ? 1 : 0) << '\n';
  }
  return s.str();
}

// Indices of the rearrangements that reached equilibrium, largest |strain jump| first.
std::vector<std::size_t> largest_jumps(const hybrid::SicResult& r, int count) {
  std::vector<std::size_t> order;
  for (std::size_t k = 0; k < r.rearrangements.size(); ++k)
    if (r.rearrangements[k].reached) order.push_back(k);
  const auto jump = [&](std::size_t k) {
    return std::abs(r.rearrangements[k].eps2_after - r.rearrangements[k].eps2_before);
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return jump(a) > jump(b); });
  if (order.size() > static_cast<std::size_t>(count)) order.resize(count);
  return order;
}

std::string picture_name(std::size_t k, const char* side, const char* what) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "rearrangement_%03zu_%s_%s.csv", k, side, what);
  return buf;
}

std::string sic_json(const SicCommandOptions& o, const StaticStart& start,
                     const hybrid::SicResult& r, const std::vector<std::size_t>& pictured) {
  std::ostringstream s;
  const auto number_list = [&](const auto& items, auto value) {
    std::string out = "[";
    for (std::size_t k = 0; k < items.size(); ++k)
      out += (k ? ", " : "") + json_number(value(items[k]));
    return out + "]";
  };
  const auto& iv = r.intervals;
  const auto& jumps = r.rearrangements;
  const double q_last = r.curve.empty() ? 0.0 : r.curve.back().q_target;
  const double eps2_last = r.curve.empty() ? 0.0 : r.curve.back().eps2;
  s << "{\n"
    << "  \"command\": \"sic\",\n"
    << "  \"sample\": " << json_string(o.sample) << ",\n"
    << "  \"n_disks\": " << start.config.disks.size() << ",\n"
    << "  \"method\": " << json_string(o.run.hybrid ? "hybrid" : "dynamic") << ",\n"
    << static_start_json(start, "  ") << ",\n"
    << "  \"dq\": " << json_number(o.run.dq) << ",\n"
    << "  \"q_max\": " << json_number(o.run.q_max) << ",\n"
    << "  \"epsilon_2_end\": " << json_number(o.run.epsilon_2_end) << ",\n"
    << "  \"epsilon_2_max\": " << json_number(o.run.epsilon_2_max) << ",\n"
    << "  \"tolerances\": {\"force\": " << json_number(o.run.equilibration.tolerances.force)
    << ", \"torque\": " << json_number(o.run.equilibration.tolerances.torque)
    << ", \"stress\": " << json_number(o.run.equilibration.tolerances.stress) << "},\n"
    << "  \"max_steps_per_increment\": " << o.run.equilibration.max_steps << ",\n"
    << "  \"stop_reason\": " << json_string(r.stop_reason) << ",\n"
    << "  \"q_last\": " << json_number(q_last) << ",\n"
    << "  \"epsilon_2_last\": " << json_number(eps2_last) << ",\n"
    << "  \"states\": " << r.curve.size() << ",\n"
    << "  \"static_states\": " << r.static_states << ",\n"
    << "  \"md_steps\": " << r.md_steps << ",\n"
    << "  \"static_seconds\": " << json_number(r.static_seconds) << ",\n"
    << "  \"dynamic_seconds\": " << json_number(r.dynamic_seconds) << ",\n"
    << "  \"stability_intervals\": " << iv.size() << ",\n"
    << "  \"interval_q\": "
    << number_list(iv, [](const hybrid::StabilityInterval& v) { return v.q_start; }) << ",\n"
    << "  \"interval_width_q\": "
    << number_list(iv, [](const hybrid::StabilityInterval& v) { return v.q_end - v.q_start; })
    << ",\n"
    << "  \"interval_width_epsilon_2\": "
    << number_list(iv, [](const hybrid::StabilityInterval& v) { return v.eps2_end - v.eps2_start; })
    << ",\n"
    << "  \"interval_polish_strain\": "
    << number_list(iv, [](const hybrid::StabilityInterval& v) { return v.polish_strain; }) << ",\n"
    << "  \"interval_end\": [";
  for (std::size_t k = 0; k < iv.size(); ++k) s << (k ? ", " : "") << json_string(iv[k].end);
  s << "],\n"
    << "  \"rearrangements\": " << jumps.size() << ",\n"
    << "  \"rearrangement_q_from\": "
    << number_list(jumps, [](const hybrid::Rearrangement& j) { return j.q_from; }) << ",\n"
    << "  \"rearrangement_q_to\": "
    << number_list(jumps, [](const hybrid::Rearrangement& j) { return j.q_to; }) << ",\n"
    << "  \"rearrangement_jump_epsilon_2\": "
    << number_list(jumps,
                   [](const hybrid::Rearrangement& j) { return j.eps2_after - j.eps2_before; })
    << ",\n"
    << "  \"rearrangement_md_steps\": "
    << number_list(jumps,
                   [](const hybrid::Rearrangement& j) { return static_cast<double>(j.md_steps); })
    << ",\n"
    << "  \"rearrangement_rattlers_freed\": "
    << number_list(
           jumps,
           [](const hybrid::Rearrangement& j) { return static_cast<double>(j.rattlers_freed); })
    << ",\n"
    << "  \"pictured_rearrangements\": [";
  for (std::size_t k = 0; k < pictured.size(); ++k) s << (k ? ", " : "") << pictured[k];
  s << "]\n}\n";
  return s.str();
}

void add_sic_options(CLI::App& cmd, SicCommandOptions& o) {
  cmd.add_option("SAMPLE", o.sample, "equilibrium configuration file (docs/file-format.md)")
      ->required();
  cmd.add_option("--dq", o.run.dq, "the increment of q (and the static step)")
      ->required()
      ->check(CLI::PositiveNumber);
  o.run.hybrid = false;
  cmd.add_flag("--hybrid", o.run.hybrid,
               "static stepping inside the stability intervals, MD only across rearrangements "
               "(default: every increment by MD)");
  cmd.add_option("--epsilon-2-end", o.run.epsilon_2_end,
                 "the run ends at the first equilibrium with epsilon_2 >= this")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd.add_option("--q-max", o.run.q_max, "the run ends at the first equilibrium with q >= this")
      ->check(CLI::PositiveNumber);
  add_md_wait_options(cmd, o.run.equilibration, o.run.epsilon_2_max);
  cmd.add_option("--dq-min", o.dq_min,
                 "static step floor: each interval's loss of stability is bracketed to it "
                 "(default dq / 1000)")
      ->check(CLI::PositiveNumber);
  cmd.add_option("--pictures", o.pictures,
                 "force networks written before and after this many largest rearrangements")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd.add_flag("--plot", o.plot, "draw the pictures at the end (granstab plot DIR)");
  cmd.add_option("--out", o.out, "output directory")->capture_default_str();
  cmd.add_option("--set", o.overrides,
                 "key=value: engine.dt_fraction, engine.skin; material.KEY=VALUE sets the "
                 "biaxial material (KEY: k_n, k_t, mu, zeta, mu_wall)");
  add_step_control_option(cmd, o.run.statics);
  add_static_start_options(cmd, o.start, false);
}

void run_sic_command(SicCommandOptions& o, const std::string& arguments) {
  split_material_settings(o.overrides, o.start);
  RunConfig rc = protocols::Invocation::from_arguments("sic", {}, o.overrides).settings_config();
  o.run.engine = protocols::read_engine_options(rc);
  rc.finish();
  const std::filesystem::path dir = o.out;
  // Validated before any output exists: a refused start leaves no file behind.
  const StaticStart start = read_static_start(o.sample, o.start, crosscheck::require_biaxial_start);
  const Configuration from = crosscheck::biaxial_start(start.config, start.config.material.mu);
  o.run.statics.dq_min = o.dq_min.value_or(1e-3 * o.run.dq);
  if (o.run.statics.dq_min > o.run.dq) throw std::invalid_argument("sic: --dq-min exceeds --dq");
  o.run.statics.hill_every = 0;  // an indicator the SIC curve does not report

  Progress progress(o.run.hybrid ? "sic --hybrid" : "sic", o.run.epsilon_2_end, !o.start.quiet);
  const auto observer = [&](double q, double eps2, hybrid::Method m) {
    char detail[64];
    std::snprintf(detail, sizeof detail, "q %.5f  %s", q, hybrid::method_name(m));
    progress.update(std::max(eps2, 0.0), detail);
  };
  // Restart points (every MD equilibrium that does not end the run) go to DIR/sic.checkpoint; a
  // run started again with the same arguments continues from the last one.
  const std::filesystem::path checkpoint_path = dir / "sic.checkpoint";
  protocols::remove_stale_temporaries({checkpoint_path});
  const std::string input_checksum = protocols::file_checksum(o.sample);
  std::optional<hybrid::SicRestart> resume;
  if (std::filesystem::exists(checkpoint_path)) {
    const protocols::Checkpoint c = protocols::Checkpoint::read(checkpoint_path);
    if (c.text("sic.arguments") != arguments || c.text("sic.input_checksum") != input_checksum)
      throw std::invalid_argument(checkpoint_path.string() +
                                  ": the checkpoint of another run (other arguments or sample); "
                                  "remove it or choose another --out");
    resume = hybrid::get_restart(c);
    if (!o.start.quiet)
      std::fprintf(stderr, "sic: continuing from %s at q = %.6g\n", checkpoint_path.c_str(),
                   resume->q);
  }
  const auto save = [&](const hybrid::SicRestart& point) {
    protocols::Checkpoint c;
    c.set("sic.arguments", arguments);
    c.set("sic.input_checksum", input_checksum);
    hybrid::put_restart(c, point, static_cast<std::size_t>(o.pictures));
    std::filesystem::create_directories(dir);
    c.write(checkpoint_path);
  };
  const hybrid::SicResult r =
      hybrid::run_sic(from, o.run, observer, save, resume ? &*resume : nullptr);
  char done[96];
  std::snprintf(done, sizeof done, "%s: %zu states, %zu rearrangements", r.stop_reason.c_str(),
                r.curve.size(), r.rearrangements.size());
  progress.finish(done);

  // Everything is formatted before the first file is written.
  const std::vector<std::size_t> pictured = largest_jumps(r, o.pictures);
  std::vector<std::pair<std::string, std::string>> files{{"sic_curve.csv", sic_curve_csv(r)}};
  for (const std::size_t k : pictured) {
    const hybrid::Rearrangement& j = r.rearrangements[k];
    files.emplace_back(picture_name(k, "before", "disks"), crosscheck::disks_csv(j.before));
    files.emplace_back(picture_name(k, "before", "network"), crosscheck::network_csv(j.before));
    files.emplace_back(picture_name(k, "after", "disks"), crosscheck::disks_csv(j.after));
    files.emplace_back(picture_name(k, "after", "network"), crosscheck::network_csv(j.after));
  }
  files.emplace_back("sic.json", sic_json(o, start, r, pictured));  // last: marks a whole run
  std::filesystem::create_directories(dir);
  for (const auto& [name, text] : files) write_file_atomically(dir / name, text);
  std::filesystem::remove(checkpoint_path);  // the run is complete
  std::printf(
      "%s SIC: %s at q = %.6g, epsilon_2 = %.6g; %zu states (%d static), %zu "
      "rearrangements, %llu MD steps; %.3g s static + %.3g s MD; outputs in %s\n",
      o.run.hybrid ? "hybrid" : "dynamic", r.stop_reason.c_str(),
      r.curve.empty() ? 0.0 : r.curve.back().q_target, r.curve.empty() ? 0.0 : r.curve.back().eps2,
      r.curve.size(), r.static_states, r.rearrangements.size(),
      static_cast<unsigned long long>(r.md_steps), r.static_seconds, r.dynamic_seconds,
      dir.string().c_str());
  std::fflush(stdout);
  if (o.plot) run_python_script("/usr/bin/python3", "scripts/plot/plot_sic.py", {dir.string()});
}

}  // namespace

void add_sic_command(CLI::App& app) {
  auto o = std::make_shared<SicCommandOptions>();
  auto* cmd = app.add_subcommand(
      "sic",
      "Stress-increment biaxial test (SPEC §3.3) of an equilibrium sample: every increment by MD, "
      "or with --hybrid static stepping inside stability intervals and MD across rearrangements; "
      "writes DIR/sic_curve.csv and DIR/sic.json");
  add_sic_options(*cmd, *o);
  cmd->callback([o] {
    // The arguments that decide the run (not --quiet, --plot), kept in its checkpoint.
    std::string arguments;
    const std::vector<std::string>& line = command_line();
    const auto at = std::find(line.begin(), line.end(), "sic");
    for (auto a = at == line.end() ? at : at + 1; a < line.end(); ++a)
      if (*a != "--quiet" && *a != "--plot") arguments += *a + '\n';
    run_sic_command(*o, arguments);
  });
}

}  // namespace granstab::cli
