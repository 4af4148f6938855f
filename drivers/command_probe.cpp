// granstab probe SAMPLE --dq X --at q,q,... [--at-q1]: the static states of the compare run at the
// given loads, and at q1, written as configurations (--save DIR) and probed by the dynamic engine:
// SIC hold of q, then random perturbations with release (drivers/stability_probe.hpp). Issue #6:
// is a static state past some q an unstable equilibrium for the dynamic module? And at q1: does
// the dynamic module hold the state where the static run stopped, as every state below q1?
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "common/atomic_file.hpp"
#include "common/io/configuration_file.hpp"
#include "crosscheck.hpp"
#include "stability_probe.hpp"
#include "static_start.hpp"

namespace granstab::cli {
namespace {

struct ProbeCommandOptions {
  std::string sample;
  std::string out = "probe-out";
  std::string save;  // directory for the static states, or empty
  std::vector<double> at;
  bool at_q1 = false;  // also the last stable state, at q1
  bool probe = true;
  crosscheck::CrosscheckOptions run;
  crosscheck::ProbeOptions probe_options;
  StaticStartOptions start;  // --mu, --kt-ratio, --set material.*, --polish, --quiet
};

std::string state_name(double q) {
  char name[64];
  std::snprintf(name, sizeof name, "static_q_%.6f.granstab", q);
  return name;
}

void run_probe(ProbeCommandOptions o) {
  if (o.at.empty() && !o.at_q1) throw std::invalid_argument("probe: give --at, --at-q1 or both");
  // Validated before any output exists: a refused start leaves no file behind.
  const Configuration sample =
      read_static_start(o.sample, o.start, crosscheck::require_biaxial_start).config;
  o.run.statics.on_progress =
      static_progress("probe (static run)", !o.start.quiet, o.run.q_max, "--q-max");
  o.run.rigid_limit = false;
  o.run.statics.hill_every = 0;  // logged only: the path does not depend on it (checked)
  o.probe_options.equilibration = o.run.equilibration;
  // The whole static run once: q1, the compliance of the bound at every state, and the states at
  // the loads asked for. Keeping them takes fixed steps (run_static_half); with --at-q1 alone the
  // run takes the adaptive steps of `granstab q1`, so its q1 state is the one `granstab q1` (same
  // SAMPLE, dq and material) stops at.
  const double tolerance = crosscheck::static_load_tolerance(o.run);
  std::vector<crosscheck::StaticState> states;
  if (!o.at.empty())
    o.run.statics.on_accepted = crosscheck::keep_static_states(o.at, tolerance, states);
  const crosscheck::CrosscheckResult full = crosscheck::run_static_half(sample, o.run);
  const std::filesystem::path dir = o.out;
  std::filesystem::create_directories(dir);
  if (!o.save.empty()) std::filesystem::create_directories(o.save);
  std::printf("q1 (static) = %.9g; mu = %.6g, dq = %.6g\n", full.statics.q1, full.mu, o.run.dq);
  std::printf("%9s %9s %4s %10s %10s %9s %11s %11s %11s %11s %9s %s\n", "q", "bound", "ratt",
              "f_net0", "hold_steps", "pert_steps", "hold_deps2", "max_loaded", "max_release",
              "final_deps2", "final/bd", "verdict");
  std::ostringstream csv;
  csv << "q,bound_eps2,rattler_overlaps,removed_rattlers,initial_max_net_force,"
         "initial_stress_error,hold_reached,hold_steps,hold_d_eps2,hold_d_epsv,draws_reached,"
         "perturbation_steps,max_loaded_d_eps2,max_released_d_eps2,final_d_eps2,final_d_epsv,"
         "stable\n";
  std::vector<crosscheck::ProbeResult> probes;
  // The loads asked for, then q1's state (the last stable one) with --at-q1: the load that names
  // the files (the one asked for), the state's own load and the state.
  struct Target {
    double q, load;
    const statics::Network* network;
  };
  std::vector<Target> targets;
  for (const double q : o.at) {
    const crosscheck::StaticState* at_q = crosscheck::static_state_at(states, q, tolerance);
    if (!at_q) {
      std::printf("%9.6f beyond the static q1 = %.9g: not probed\n", q, full.statics.q1);
      continue;
    }
    targets.push_back({q, at_q->load, &at_q->network});
  }
  if (o.at_q1) targets.push_back({full.statics.q1, full.statics.q1, &full.statics.network_at_q1});
  for (const auto& [q, load, network] : targets) {
    const Configuration state = crosscheck::configuration_of_static_state(*network, full.start);
    const std::vector<char> overlaps = crosscheck::overlapping_rattlers(*network, state);
    if (!o.save.empty()) {
      const std::filesystem::path file = std::filesystem::path(o.save) / state_name(q);
      write_configuration(state, file);
      // The state the probe starts the engine from: without the overlapping rattlers.
      if (o.probe_options.remove_overlapping_rattlers)
        write_configuration(crosscheck::without_disks(state, overlaps),
                            std::filesystem::path(file).replace_extension(".no-overlaps.granstab"));
    }
    if (!o.probe) continue;
    const double bound = crosscheck::static_bound_eps2(full.statics.curve, load, full.pressure,
                                                       o.run.equilibration.tolerances);
    const crosscheck::ProbeResult p =
        crosscheck::probe_static_state(state, overlaps, load, bound, o.probe_options);
    probes.push_back(p);
    std::printf("%9.6f %9.2e %4d %10.2e %10llu %9llu %11.3e %11.3e %11.3e %11.3e %9.3g %s\n", p.q,
                p.bound_eps2, p.rattler_overlaps, p.initial_max_net_force,
                static_cast<unsigned long long>(p.hold_steps),
                static_cast<unsigned long long>(p.perturbation_steps), p.hold_d_eps2,
                p.max_loaded_d_eps2, p.max_released_d_eps2, p.final_d_eps2,
                std::abs(p.final_d_eps2) / p.bound_eps2, p.stable ? "stable" : "moves");
    std::fflush(stdout);
    csv << crosscheck::json_number(p.q) << ',' << crosscheck::json_number(p.bound_eps2) << ','
        << p.rattler_overlaps << ',' << p.removed_rattlers << ','
        << crosscheck::json_number(p.initial_max_net_force) << ','
        << crosscheck::json_number(p.initial_stress_error) << ',' << (p.hold_reached ? 1 : 0) << ','
        << p.hold_steps << ',' << crosscheck::json_number(p.hold_d_eps2) << ','
        << crosscheck::json_number(p.hold_d_epsv) << ',' << p.draws_reached << ','
        << p.perturbation_steps << ',' << crosscheck::json_number(p.max_loaded_d_eps2) << ','
        << crosscheck::json_number(p.max_released_d_eps2) << ','
        << crosscheck::json_number(p.final_d_eps2) << ',' << crosscheck::json_number(p.final_d_epsv)
        << ',' << (p.stable ? 1 : 0) << '\n';
  }
  if (o.probe) {
    write_file_atomically(dir / "probe.csv", csv.str());
    std::printf("static states stable up to q = %.6g (of those probed); outputs in %s\n",
                crosscheck::stable_up_to(probes), dir.string().c_str());
  }
}

}  // namespace

void add_probe_command(CLI::App& app) {
  auto o = std::make_shared<ProbeCommandOptions>();
  auto* cmd = app.add_subcommand(
      "probe",
      "The static states of `granstab compare` at given q as configurations (--save DIR), and "
      "their dynamic stability: SIC hold of q, then random perturbations with release; writes "
      "DIR/probe.csv");
  cmd->add_option("SAMPLE", o->sample, "equilibrium configuration file (docs/file-format.md)")
      ->required();
  cmd->add_option("--dq", o->run.dq, "delta q of the static run (as in compare)")
      ->required()
      ->check(CLI::PositiveNumber);
  add_static_start_options(*cmd, o->start, true);
  cmd->add_option("--static-substeps", o->run.static_substeps, "as in compare")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--at", o->at, "loads q of the static states, comma-separated")->delimiter(',');
  cmd->add_flag("--at-q1", o->at_q1,
                "also the last stable state, at q1; without --at the static run takes the "
                "adaptive steps of `granstab q1`, so this is the state `granstab q1` stops at");
  cmd->add_option("--f0", o->probe_options.f0,
                  "perturbation forces in [-f0, f0] (units of aP, SPEC 3.5); 0: hold only")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--draws", o->probe_options.draws, "perturbation draws, each released")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--seed", o->probe_options.seed, "seed of the perturbation draws")
      ->capture_default_str();
  cmd->add_flag("!--keep-rattlers", o->probe_options.remove_overlapping_rattlers,
                "keep the rattlers that overlap the static state's disks (default: removed "
                "before the probe, they carry no force in the static state)");
  cmd->add_option("--save", o->save, "write the static states to this directory");
  cmd->add_flag("!--no-probe", o->probe, "only write the states (with --save)");
  cmd->add_option("--out", o->out, "output directory (probe.csv)")->capture_default_str();
  cmd->callback([o] { run_probe(*o); });
}

}  // namespace granstab::cli
