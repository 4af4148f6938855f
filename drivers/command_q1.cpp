// granstab q1 SAMPLE: static stepping of the biaxial test from the sample's equilibrium state up
// to the loss of stability of its contact network (SPEC §4, STATIC.md §S3). The stepping, the
// criteria and the bracketing live in static/q1.hpp; this file parses, calls and writes.
#include <CLI/CLI.hpp>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include "commands.hpp"
#include "common/atomic_file.hpp"
#include "common/io/configuration_file.hpp"
#include "common/io/json_text.hpp"
#include "crosscheck.hpp"
#include "provenance.hpp"
#include "static_start.hpp"
#include "static/q1.hpp"
#include "static/rigid_limit.hpp"

namespace granstab::cli {
namespace {

struct Q1CommandOptions {
  std::string sample;
  std::string out = ".";
  std::string control = "stress";
  statics::Q1Options q1;
  StaticStartOptions start;
};

// static_curve.csv and unstable_mode.csv: the one writer shared with `granstab compare`
// (drivers/crosscheck.hpp).

std::string q1_json(const Q1CommandOptions& o, const StaticStart& start,
                    const statics::StabilityResult& r, const statics::RigidLimitResult& rigid,
                    double seconds) {
  std::ostringstream s;
  s << "{\n"
    << "  \"sample\": " << json_string(o.sample) << ",\n"
    << "  \"control\": " << json_string(o.control) << ",\n"
    << static_start_json(start, "  ") << ",\n"
    << "  \"q1\": " << json_number(r.q1) << ",\n"
    << "  \"q1_bracket\": [" << json_number(r.q1_bracket[0]) << ", " << json_number(r.q1_bracket[1])
    << "],\n"
    << "  \"criterion\": " << json_string(statics::criterion_name(r.criterion)) << ",\n"
    << "  \"detail\": " << json_string(r.detail) << ",\n"
    << "  \"n_sliding_at_q1\": " << r.sliding_at_q1.size() << ",\n"
    << "  \"sliding_contacts_at_q1\": [";
  for (std::size_t c = 0; c < r.sliding_at_q1.size(); ++c) {
    const statics::SlidingContact& k = r.sliding_at_q1[c];
    s << (c ? ", " : "") << "{\"i\": " << k.i << ", \"j\": " << k.j << ", \"k\": [" << k.k1 << ", "
      << k.k2 << "], \"f_n\": " << json_number(k.f_n) << ", \"f_t\": " << json_number(k.f_t) << "}";
  }
  s << "],\n"
    // q_max of the frozen initial network (SPEC §4.5); null when unbounded or failed, see status.
    << "  \"q_max_rigid\": " << json_number(rigid.q_max) << ",\n"
    << "  \"q_max_rigid_status\": " << json_string(rigid.status) << ",\n"
    << "  \"n_disks\": " << start.config.disks.size() << ",\n"
    << "  \"n_contacts\": " << start.config.contacts.size() << ",\n"
    << "  \"step_control\": " << json_string(statics::step_control_name(r.step_control)) << ",\n"
    << "  \"states\": " << r.steps + 1 << ",\n"
    << "  \"steps\": " << r.steps << ",\n"
    << "  \"attempts\": " << r.attempts << ",\n"
    << "  \"interpolated_rows\": " << r.interpolated_rows << ",\n"
    << "  \"rejected_steps\": {" <<
      [&] {
        std::string list;
        for (const auto& [reason, count] : r.rejected)
          list += (list.empty() ? "" : ", ") + json_string(reason) + ": " + std::to_string(count);
        return list;
      }()
    << "},\n"
    << "  \"dq\": " << json_number(o.q1.dq) << ",\n"
    << "  \"dq_min\": " << json_number(o.q1.dq_min) << ",\n"
    << "  \"seconds_assembly\": " << json_number(r.timings.assembly) << ",\n"
    << "  \"seconds_factorisation\": " << json_number(r.timings.factorisation) << ",\n"
    << "  \"seconds_complementarity\": " << json_number(r.timings.complementarity) << ",\n"
    << "  \"seconds_corrector\": " << json_number(r.timings.corrector) << ",\n"
    << "  \"wall_seconds\": " << json_number(seconds) << ",\n"
    << "  \"granstab_version\": " << json_string(granstab_version()) << ",\n"
    << "  \"blas\": " << json_string(blas_library()) << "\n"
    << "}\n";
  return s.str();
}

void run_q1(Q1CommandOptions o) {
  const auto start = std::chrono::steady_clock::now();
  // Validated before any output exists: a refused start leaves no file behind.
  const StaticStart sample = read_static_start(o.sample, o.start);
  o.q1.control = o.control == "strain" ? statics::Control::strain : statics::Control::stress;
  // The rigid-limit bound first: it is the progress lines' target for q1 (an upper bound).
  const statics::RigidLimitResult rigid = statics::rigid_limit(sample.config);
  const bool stress = o.q1.control == statics::Control::stress;
  o.q1.on_progress = static_progress(
      "q1", !o.start.quiet, stress ? std::min(o.q1.load_stop, rigid.q_max) : o.q1.load_stop,
      "q_max_rigid (an upper bound of q1) or --stop");
  const statics::StabilityResult r = statics::find_q1(sample.config, o.q1);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::filesystem::path dir = o.out;
  std::filesystem::create_directories(dir);
  write_file_atomically(dir / "static_curve.csv", crosscheck::static_curve_csv(r));
  write_file_atomically(dir / "unstable_mode.csv", crosscheck::mode_csv(r));
  write_file_atomically(dir / "q1.json", q1_json(o, sample, r, rigid, seconds));
  char line[256];
  std::snprintf(line, sizeof line,
                "q1 = %.9g in [%.9g, %.9g] (%s), %zu sliding, %d steps, q_max_rigid = %.9g (%s), "
                "%.3g s\n",
                r.q1, r.q1_bracket[0], r.q1_bracket[1], statics::criterion_name(r.criterion),
                r.sliding_at_q1.size(), r.steps, rigid.q_max, rigid.status.c_str(), seconds);
  std::cout << line << std::flush;
}

}  // namespace

void add_q1_command(CLI::App& app) {
  auto options = std::make_shared<Q1CommandOptions>();
  auto* cmd = app.add_subcommand(
      "q1",
      "Static stepping (SPEC §4) of the biaxial test from a sample's equilibrium up to the "
      "loss of stability q1; writes DIR/static_curve.csv, DIR/q1.json, DIR/unstable_mode.csv");
  cmd->add_option("SAMPLE", options->sample, "configuration file (docs/file-format.md)")
      ->required();
  cmd->add_option("--dq", options->q1.dq,
                  "load step: delta q (stress control) or delta epsilon_2 (strain control)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--dq-min", options->q1.dq_min, "step floor, the bracket tolerance of q1")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--out", options->out, "output directory")->capture_default_str();
  cmd->add_option("--control", options->control, "stress (q raised) or strain (epsilon_2 raised)")
      ->capture_default_str()
      ->check(CLI::IsMember({"stress", "strain"}));
  cmd->add_option("--max-steps", options->q1.max_steps, "stop after this many accepted steps")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--stop", options->q1.load_stop,
                  "stop once the load parameter (q, or epsilon_2) passes this value");
  add_hill_option(*cmd, options->q1.hill_every);
  add_step_control_option(*cmd, options->q1);
  add_static_start_options(*cmd, options->start, true);
  cmd->callback([options] { run_q1(*options); });
}

}  // namespace granstab::cli
