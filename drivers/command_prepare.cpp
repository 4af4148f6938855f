// granstab prepare CONFIG.toml: a seeded random gas compacted isotropically under P to
// equilibrium (SPEC §3.2); writes the sample, a JSON summary and optionally a CSV time series
// and VTK snapshots. The settings are documented in docs/protocols.md.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "resumable.hpp"
#include "common/io/configuration_file.hpp"
#include "common/io/csv_writer.hpp"
#include "common/measurements.hpp"
#include "common/progress.hpp"
#include "common/run_config.hpp"
#include "dynamic/protocols/compaction.hpp"
#include "dynamic/protocols/json_summary.hpp"
#include "dynamic/protocols/random_gas.hpp"
#include "dynamic/protocols/record.hpp"
#include "dynamic/protocols/settings.hpp"
#include "dynamic/protocols/snapshots.hpp"

namespace granstab::cli {
namespace {

struct PrepareOptions {
  std::string settings;
  std::vector<std::string> overrides;
  bool quiet = false;
};

struct PrepareSettings {
  protocols::GasOptions gas;
  std::uint64_t seed = 1;
  Material material;
  protocols::CompactionOptions compaction;
  EngineOptions engine;
  std::filesystem::path sample, summary;
  std::optional<std::filesystem::path> csv;
  std::uint64_t record_interval = 10000;
  protocols::SnapshotSettings snapshots;
  protocols::GuardSettings guard;
};

PrepareSettings read_prepare_settings(const protocols::Invocation& invocation) {
  RunConfig rc = invocation.settings_config();
  PrepareSettings s;
  s.gas.n = static_cast<int>(rc.integer("sample.n", 100, 1, 10'000'000));
  s.gas.boundary = rc.choice("sample.boundary", "periodic", {"periodic", "walls"}) == "walls"
                       ? Boundary::walls
                       : Boundary::periodic;
  s.gas.phi = rc.number("sample.gas_phi", 0.2, 0.01, 0.5);
  s.gas.aspect = rc.number("sample.aspect", 1.0, 0.1, 10.0);
  s.seed = static_cast<std::uint64_t>(rc.integer("sample.seed", 1, 0, INT64_MAX));
  s.material = protocols::read_material(rc, Material::from_kappa(1e4, 1.0, 0.15, 1.0));
  s.compaction.strain_rate = rc.number("compaction.strain_rate", 0.0, 0.0, 1.0);
  s.compaction.cell_mass_factor = rc.number("compaction.cell_mass_factor", 1.0, 1e-3, 1e3);
  s.compaction.equilibration = protocols::read_equilibration(rc);
  s.engine = protocols::read_engine_options(rc);
  s.sample = protocols::required_path(rc, "output.sample");
  s.summary = rc.path("output.summary")
                  .value_or(std::filesystem::path(s.sample).replace_extension(".json"));
  s.csv = rc.path("output.csv");
  s.record_interval =
      static_cast<std::uint64_t>(rc.integer("output.record_interval", 10000, 1, INT64_MAX));
  s.snapshots = protocols::read_snapshot_settings(rc);
  s.guard = protocols::read_guard_settings(
      rc, std::filesystem::path(s.sample).replace_extension(".checkpoint"));
  rc.finish();
  return s;
}

}  // namespace

void run_prepare(const protocols::Invocation& invocation, bool quiet,
                 const protocols::Checkpoint* checkpoint) {
  // Settings errors come before any output.
  const PrepareSettings s = read_prepare_settings(invocation);
  Progress progress("prepare", 0.0, !quiet);
  protocols::RunGuard guard(s.guard, "prepare");

  std::optional<Engine> engine;
  double gas_phi = 0.0, wall_before = 0.0;
  protocols::LoopControl control;
  Configuration gas;
  if (checkpoint) {
    engine.emplace(checkpoint->configuration("engine"), s.engine);
    gas_phi = checkpoint->number("prepare.gas_phi");
    wall_before = checkpoint->number("run.wall_seconds");
    control.cursor = protocols::get_cursor(*checkpoint);
    control.resume = true;
  } else {
    std::mt19937_64 rng(s.seed);
    gas = protocols::random_gas(s.gas, s.material, rng);
    gas_phi = solid_fraction(gas);
    std::ostringstream rng_state;
    rng_state << rng;
    gas.rng_state = rng_state.str();
    engine.emplace(gas, s.engine);
  }
  std::optional<CsvWriter> csv;
  if (s.csv) csv.emplace(*s.csv, protocols::state_columns(), 30.0);
  protocols::SnapshotWriter snapshots(s.snapshots);
  if (checkpoint) {
    if (csv) protocols::restore_csv(*csv, checkpoint->count("output.csv.bytes"));
    snapshots.restore(checkpoint->has("output.vtk.next")
                          ? std::optional(checkpoint->count("output.vtk.next"))
                          : std::nullopt,
                      checkpoint->count("output.vtk.written"));
  } else {
    snapshots.maybe_write(gas, 0);
  }

  const auto build = [&](const Engine& e, const protocols::Cursor& cursor) {
    protocols::Checkpoint c =
        checkpoint_head(invocation, e, cursor, "none", wall_before + progress.elapsed_seconds());
    c.set_number("prepare.gas_phi", gas_phi);
    if (csv) c.set_count("output.csv.bytes", csv->text().size());
    if (snapshots.next_step()) c.set_count("output.vtk.next", *snapshots.next_step());
    c.set_count("output.vtk.written", snapshots.written());
    return c;
  };
  guard.on_write([&] {
    if (csv) csv->flush();
  });
  control.hooks = guard_hooks(guard, build);

  DecayEstimate decay;
  std::optional<std::uint64_t> first_step;
  const auto observer = [&](const Engine& e, const Configuration& state,
                            const EquilibriumReport& r) {
    const std::uint64_t step = e.step_count();
    if (csv && step % s.record_interval < s.compaction.equilibration.check_interval) {
      csv->row(protocols::state_row(state, measure(state)));
    }
    snapshots.maybe_write(state, step);
    // The compaction has no known end: the ETA extrapolates the decay of the slowest residual
    // (relative to its tolerance) at this run's measured wall time per step.
    const EquilibriumTolerances& tol = s.compaction.equilibration.tolerances;
    decay.add(static_cast<double>(step),
              std::max({r.max_net_force / tol.force, r.max_net_torque / tol.torque,
                        r.stress_error[0] / tol.stress, r.stress_error[1] / tol.stress}));
    if (!first_step) first_step = step;
    std::optional<double> seconds_left;
    const auto steps_left = decay.steps_left();
    if (steps_left && step > *first_step) {
      seconds_left =
          *steps_left * progress.elapsed_seconds() / static_cast<double>(step - *first_step);
    }
    char detail[160];
    std::snprintf(detail, sizeof detail,
                  "Phi %.4f  max force %.3g  torque %.3g  stress err %.3g %.3g",
                  solid_fraction(state), r.max_net_force, r.max_net_torque, r.stress_error[0],
                  r.stress_error[1]);
    progress.update_estimated(static_cast<double>(step), seconds_left, "residual decay", detail);
    return true;
  };
  Configuration state;
  const protocols::CompactionResult result =
      protocols::compact_isotropically(*engine, s.compaction, state, observer, control);
  const double wall_seconds = wall_before + progress.elapsed_seconds();

  const Measurements m = measure(state);
  write_configuration(state, s.sample);
  if (csv) {
    csv->row(protocols::state_row(state, m));
    csv->flush();
  }
  snapshots.write_final(state);

  protocols::JsonObject material;
  material.add("kappa", s.material.kappa())
      .add("kt_over_kn", s.material.kt_over_kn())
      .add("mu_prep", s.material.mu)
      .add("zeta", s.material.zeta)
      .add("mu_wall", s.material.mu_wall);
  protocols::JsonObject summary;
  summary.add("command", "prepare")
      .add("settings", invocation.settings)
      .add("sample", s.sample.string())
      .add("seed", s.seed)
      .add("n_disks", static_cast<std::int64_t>(s.gas.n))
      .add("boundary", s.gas.boundary == Boundary::walls ? "walls" : "periodic")
      .add("gas_phi", gas_phi)
      .add("material", material)
      .add("compaction_strain_rate", s.compaction.strain_rate)
      .add("compaction_cell_mass_factor", s.compaction.cell_mass_factor)
      .add("dt", engine->dt())
      .add("steps_strain_rate", result.strain_rate_steps)
      .add("steps_stress", result.stress_steps)
      .add("steps", engine->step_count())
      .add("wall_seconds", wall_seconds)
      .add("reached_equilibrium", result.reached)
      .add("phi", m.phi)
      .add("z", m.z)
      .add("x0", m.x0)
      .add("measurements", protocols::measurements_json(m))
      .add("equilibrium",
           protocols::equilibrium_json(result.report, s.compaction.equilibration.tolerances));
  protocols::write_json(s.summary, summary);
  guard.finish();

  char detail[160];
  std::snprintf(detail, sizeof detail, "%llu steps, Phi %.4f, z %.3f, x0 %.3f",
                static_cast<unsigned long long>(engine->step_count()), m.phi, m.z, m.x0);
  progress.finish(detail);
  if (!result.reached) {
    throw std::runtime_error("prepare: no equilibrium within equilibrium.max_steps = " +
                             std::to_string(s.compaction.equilibration.max_steps) +
                             " (the last state is in " + s.sample.string() + ")");
  }
}

void add_prepare_command(CLI::App& app) {
  auto options = std::make_shared<PrepareOptions>();
  auto* cmd = app.add_subcommand(
      "prepare", "Random gas compacted isotropically under P to equilibrium (SPEC §3.2)");
  cmd->add_option("CONFIG", options->settings, "settings (TOML, docs/protocols.md)")->required();
  cmd->add_option("--set", options->overrides, "override a setting, key=value");
  cmd->add_flag("--quiet", options->quiet, "no progress on stderr");
  cmd->callback([options] {
    run_prepare(protocols::Invocation::start("prepare", options->settings, options->overrides),
                options->quiet, nullptr);
  });
}

}  // namespace granstab::cli
