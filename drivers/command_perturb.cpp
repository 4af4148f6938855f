// granstab perturb CONFIG.toml: SPEC §3.5. From an equilibrium sample under stress control,
// random constant forces on every disk (components uniform in [-f0, f0]), new equilibrium,
// strain changes recorded; repeated with fresh draws. Settings: docs/protocols.md.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
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
#include "dynamic/protocols/biaxial.hpp"
#include "dynamic/protocols/json_summary.hpp"
#include "dynamic/protocols/perturbation.hpp"
#include "dynamic/protocols/settings.hpp"

namespace granstab::cli {
namespace {

struct PerturbCommandOptions {
  std::string settings;
  std::vector<std::string> overrides;
  bool quiet = false;
};

struct PerturbSettings {
  std::filesystem::path input;
  Configuration sample;
  Material material;
  std::optional<double> q;
  std::uint64_t seed = 1;
  protocols::PerturbationOptions perturbation;
  EngineOptions engine;
  std::filesystem::path csv, summary;
  std::optional<std::filesystem::path> final_sample;
  protocols::GuardSettings guard;
};

PerturbSettings read_perturb_settings(const protocols::Invocation& invocation) {
  RunConfig rc = invocation.settings_config();
  PerturbSettings s;
  s.input = protocols::existing_file(rc, "input.sample");
  s.sample = read_configuration(s.input);
  s.material = protocols::read_material(rc, s.sample.material);
  if (rc.contains("perturb.q")) s.q = rc.number("perturb.q", 0.0, -0.99, 100.0);
  s.seed = static_cast<std::uint64_t>(rc.integer("perturb.seed", 1, 0, INT64_MAX));
  s.perturbation.f0 = rc.number("perturb.f0", 1e-3, 1e-12, 10.0);
  s.perturbation.repetitions =
      static_cast<int>(rc.integer("perturb.repetitions", 10, 1, 1'000'000));
  s.perturbation.release = rc.boolean("perturb.release", true);
  s.perturbation.failure_delta_epsilon_2 =
      rc.number("perturb.failure_delta_epsilon_2", 0.1, 1e-9, 0.9);
  s.perturbation.equilibration = protocols::read_equilibration(rc);
  s.engine = protocols::read_engine_options(rc);
  s.csv = protocols::required_path(rc, "output.csv");
  s.summary =
      rc.path("output.summary").value_or(std::filesystem::path(s.csv).replace_extension(".json"));
  s.final_sample = rc.path("output.sample");
  s.guard = protocols::read_guard_settings(
      rc, std::filesystem::path(s.csv).replace_extension(".checkpoint"));
  rc.finish();
  return s;
}

constexpr int initial_phase = 0;  // the reference equilibrium; draws are phases 1 and 2

}  // namespace

void run_perturb(const protocols::Invocation& invocation, bool quiet,
                 const protocols::Checkpoint* checkpoint) {
  // Settings errors come before any output.
  const PerturbSettings s = read_perturb_settings(invocation);
  constexpr double pressure = 1.0;
  const std::string input_checksum = protocols::file_checksum(s.input);
  if (checkpoint) require_same_input(*checkpoint, s.input.string(), input_checksum);
  const double wall_before = checkpoint ? checkpoint->number("run.wall_seconds") : 0.0;
  // The held stresses: sigma_1 = P and sigma_2 = P (1 + q), q given or the sample's own (its
  // prescribed q if both axes were stress-controlled, else its measured q).
  const Stage& st = s.sample.stage;
  const bool stress_controlled =
      st.control[0] == LengthControl::stress && st.control[1] == LengthControl::stress;
  const double q = s.q.value_or(stress_controlled ? st.sigma_ext[1] / st.sigma_ext[0] - 1.0
                                                  : measure(s.sample).q);
  Engine engine(checkpoint ? checkpoint->configuration("engine") : s.sample, s.engine);
  if (!checkpoint) {
    engine.set_material(s.material);
    engine.set_stress_control(0, pressure);
    engine.set_stress_control(1, pressure * (1.0 + q));
  }

  Progress progress("perturb", s.perturbation.repetitions, !quiet);
  protocols::Cursor resume_cursor;
  if (checkpoint) resume_cursor = protocols::get_cursor(*checkpoint);
  const bool resume_initial = checkpoint && resume_cursor.phase == initial_phase;
  std::optional<CsvWriter> csv;
  int draws = 0, reached = 0;
  bool flowed = false;  // a wait ended by the strain guard
  protocols::EquilibrationResult initial;
  protocols::RunGuard guard(s.guard, "perturb");
  const auto build = [&](const Engine& e, const protocols::Cursor& cursor) {
    protocols::Checkpoint c = checkpoint_head(invocation, e, cursor, input_checksum,
                                              wall_before + progress.elapsed_seconds());
    if (csv) {
      c.set_count("output.csv.bytes", csv->text().size());
      c.set_count("perturb.draws", static_cast<std::uint64_t>(draws));
      c.set_count("perturb.reached", static_cast<std::uint64_t>(reached));
      c.set_count("perturb.initial_steps", initial.steps);
    }
    return c;
  };
  guard.on_write([&] {
    if (csv) csv->flush();
  });
  const protocols::LoopHooks hooks = guard_hooks(guard, build);

  Configuration state;
  if (!checkpoint || resume_initial) {
    // The reference equilibrium at the held stresses (usually reached at once).
    protocols::LoopControl control{hooks, protocols::Cursor{}, resume_initial};
    if (resume_initial) control.cursor = resume_cursor;
    control.cursor.phase = initial_phase;
    const double epsilon_2_start = strains(s.sample)[1];
    const auto flows = [&](const Engine& e, const Configuration&, const EquilibriumReport&) {
      return std::abs(protocols::axial_strain(e) - epsilon_2_start) <=
             s.perturbation.failure_delta_epsilon_2;
    };
    initial = protocols::run_to_equilibrium(engine, s.perturbation.equilibration, state, flows, {},
                                            {}, control);
    if (!initial.reached) {
      guard.finish();
      throw std::runtime_error(
          "perturb: the sample does not reach equilibrium at q = " + std::to_string(q) +
          " before any perturbation" +
          (initial.aborted ? " (the strain guard fired: epsilon_2 moved by more than "
                             "perturb.failure_delta_epsilon_2; the sample flows)"
                           : " (equilibrium.max_steps reached)"));
    }
  } else {
    initial.reached = true;
    initial.steps = checkpoint->count("perturb.initial_steps");
    draws = static_cast<int>(checkpoint->count("perturb.draws"));
    reached = static_cast<int>(checkpoint->count("perturb.reached"));
  }
  csv.emplace(
      s.csv,
      std::vector<std::string>{"draw", "epsilon_2_before", "epsilon_v_before", "delta_epsilon_2",
                               "delta_epsilon_v", "loaded_steps", "loaded_reached",
                               "delta_epsilon_2_released", "delta_epsilon_v_released",
                               "released_steps", "released_reached", "q", "max_net_force"},
      30.0);
  if (checkpoint && !resume_initial) {
    protocols::restore_csv(*csv, checkpoint->count("output.csv.bytes"));
  }
  std::mt19937_64 rng(s.seed);  // a resumed draw sets it back from the cursor
  const auto on_record = [&](const Engine& e, const Configuration& now,
                             const protocols::PerturbationRecord& r) {
    guard.check(e);
    const Measurements m = measure(now);
    csv->row({static_cast<double>(r.draw), r.epsilon_2_before, r.epsilon_v_before,
              r.delta_epsilon_2, r.delta_epsilon_v, static_cast<double>(r.loaded.steps),
              r.loaded.reached ? 1.0 : 0.0, r.delta_epsilon_2_released, r.delta_epsilon_v_released,
              static_cast<double>(r.released.steps), r.released.reached ? 1.0 : 0.0, m.q,
              m.max_net_force});
    ++draws;
    reached += r.loaded.reached && (!s.perturbation.release || r.released.reached);
    flowed = flowed || r.loaded.aborted || r.released.aborted;
    char detail[96];
    std::snprintf(detail, sizeof detail, "delta epsilon_2 %.3g", r.delta_epsilon_2);
    progress.update(r.draw, detail);
    return true;
  };
  protocols::LoopControl draws_control{hooks, protocols::Cursor{}, checkpoint && !resume_initial};
  if (draws_control.resume) draws_control.cursor = resume_cursor;
  protocols::run_perturbations(engine, s.perturbation, rng, state, on_record, {}, draws_control);
  const double wall_seconds = wall_before + progress.elapsed_seconds();
  progress.finish();
  std::ostringstream rng_state;
  rng_state << rng;
  state.rng_state = rng_state.str();
  csv->flush();
  if (s.final_sample) write_configuration(state, *s.final_sample);
  const Measurements m = measure(state);
  protocols::JsonObject summary;
  summary.add("command", "perturb")
      .add("settings", invocation.settings)
      .add("input", s.input.string())
      .add("q", q)
      .add("f0", s.perturbation.f0)
      .add("seed", s.seed)
      .add("release", s.perturbation.release)
      .add("draws", static_cast<std::int64_t>(draws))
      .add("draws_reaching_equilibrium", static_cast<std::int64_t>(reached))
      .add("epsilon_2_final", m.epsilon_2)
      .add("epsilon_v_final", m.epsilon_v)
      .add("initial_equilibrium_steps", initial.steps)
      .add("steps", engine.step_count() - s.sample.step)
      .add("wall_seconds", wall_seconds)
      .add("csv", s.csv.string());
  protocols::write_json(s.summary, summary);
  guard.finish();
  if (reached < draws) {
    throw std::runtime_error("perturb: draw " + std::to_string(draws) +
                             " did not reach equilibrium" +
                             (flowed ? " (the strain guard fired: epsilon_2 moved by more than "
                                       "perturb.failure_delta_epsilon_2; the sample flows)"
                                     : " within equilibrium.max_steps"));
  }
}

void add_perturb_command(CLI::App& app) {
  auto options = std::make_shared<PerturbCommandOptions>();
  auto* cmd =
      app.add_subcommand("perturb",
                         "Random constant forces on every disk of an equilibrium sample, new "
                         "equilibrium, strain changes; repeated (SPEC §3.5)");
  cmd->add_option("CONFIG", options->settings, "settings (TOML, docs/protocols.md)")->required();
  cmd->add_option("--set", options->overrides, "override a setting, key=value");
  cmd->add_flag("--quiet", options->quiet, "no progress on stderr");
  cmd->callback([options] {
    run_perturb(protocols::Invocation::start("perturb", options->settings, options->overrides),
                options->quiet, nullptr);
  });
}

}  // namespace granstab::cli
