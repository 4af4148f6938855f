// granstab creep CONFIG.toml: SPEC §3.4. An SRC test from a prepared sample up to a chosen strain
// or q, then stress control holding that q until equilibrium; the strain change is the creep
// strain. Optionally SRC resumes afterwards. Settings: docs/protocols.md.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "resumable.hpp"
#include "common/io/configuration_file.hpp"
#include "common/io/csv_writer.hpp"
#include "common/measurements.hpp"
#include "common/progress.hpp"
#include "common/run_config.hpp"
#include "dynamic/protocols/creep.hpp"
#include "dynamic/protocols/json_summary.hpp"
#include "dynamic/protocols/record.hpp"
#include "dynamic/protocols/settings.hpp"

namespace granstab::cli {
namespace {

struct CreepCommandOptions {
  std::string settings;
  std::vector<std::string> overrides;
  bool quiet = false;
};

struct CreepSettings {
  std::filesystem::path input;
  Configuration sample;
  Material material;
  protocols::StrainRateOptions src;
  std::optional<double> at_epsilon_2, at_q;
  double epsilon_2_max = 0.05;
  bool resume = false;
  protocols::CreepOptions creep;
  EngineOptions engine;
  std::filesystem::path csv, summary;
  std::optional<std::filesystem::path> final_sample, hold_sample;
  protocols::GuardSettings guard;
};

CreepSettings read_creep_settings(const protocols::Invocation& invocation) {
  RunConfig rc = invocation.settings_config();
  CreepSettings s;
  s.input = protocols::existing_file(rc, "input.sample");
  s.sample = read_configuration(s.input);
  s.material = protocols::read_material(rc, s.sample.material);
  s.src.gamma = rc.number("creep.gamma", 1e-4, 1e-12, 1.0);
  s.src.record_interval = rc.number("creep.record_interval", 1e-4, 1e-12, 1.0);
  s.epsilon_2_max = rc.number("creep.epsilon_2_max", 0.05, 1e-12, 0.9);
  if (rc.contains("creep.at_epsilon_2")) {
    s.at_epsilon_2 = rc.number("creep.at_epsilon_2", 0.0, 1e-12, s.epsilon_2_max);
  }
  if (rc.contains("creep.at_q")) s.at_q = rc.number("creep.at_q", 0.0, 1e-12, 100.0);
  if (s.at_epsilon_2.has_value() == s.at_q.has_value()) {
    throw std::invalid_argument(rc.source_name() +
                                ": creep: give exactly one of at_epsilon_2 and at_q");
  }
  s.resume = rc.boolean("creep.resume", false);
  s.creep.failure_delta_epsilon_2 = rc.number("creep.failure_delta_epsilon_2", 0.1, 1e-9, 0.9);
  s.creep.equilibration = protocols::read_equilibration(rc);
  s.engine = protocols::read_engine_options(rc);
  s.csv = protocols::required_path(rc, "output.csv");
  s.summary =
      rc.path("output.summary").value_or(std::filesystem::path(s.csv).replace_extension(".json"));
  s.final_sample = rc.path("output.sample");
  s.hold_sample = rc.path("output.hold_sample");
  s.guard = protocols::read_guard_settings(
      rc, std::filesystem::path(s.csv).replace_extension(".checkpoint"));
  rc.finish();
  return s;
}

// Phases of a creep run, as cursors and the CSV's phase column give them.
constexpr int src_phase = 0, hold_phase = 1, resumed_src_phase = 2;

}  // namespace

void run_creep(const protocols::Invocation& invocation, bool quiet,
               const protocols::Checkpoint* checkpoint) {
  // Settings errors come before any output.
  const CreepSettings s = read_creep_settings(invocation);
  constexpr double pressure = 1.0;
  const std::string input_checksum = protocols::file_checksum(s.input);
  if (checkpoint) require_same_input(*checkpoint, s.input.string(), input_checksum);
  const double wall_before = checkpoint ? checkpoint->number("run.wall_seconds") : 0.0;
  Engine engine(checkpoint ? checkpoint->configuration("engine") : s.sample, s.engine);
  if (!checkpoint) protocols::begin_biaxial_stage(engine, s.material, pressure);

  std::vector<std::string> columns = protocols::state_columns();
  columns.emplace_back("phase");  // 0: SRC, 1: held q, 2: SRC resumed
  CsvWriter csv(s.csv, columns, 30.0);
  int phase = src_phase;
  const auto record = [&](const Configuration& st) {
    std::vector<double> row = protocols::state_row(st, measure(st));
    row.push_back(phase);
    csv.row(row);
  };
  Progress progress("creep", 0.0, !quiet);
  // Where the run stands (restored from the checkpoint): the hold's q and, once it has ended,
  // its result.
  protocols::Cursor resume_cursor;
  double q_hold = 0.0;
  protocols::CreepResult creep;
  if (checkpoint) {
    protocols::restore_csv(csv, checkpoint->count("output.csv.bytes"));
    resume_cursor = protocols::get_cursor(*checkpoint);
    phase = resume_cursor.phase;
    if (phase >= hold_phase) q_hold = checkpoint->number("creep.q_hold");
    if (phase == resumed_src_phase) {
      creep.q_hold = q_hold;
      creep.epsilon_2_switch = checkpoint->number("creep.epsilon_2_switch");
      creep.epsilon_v_switch = checkpoint->number("creep.epsilon_v_switch");
      creep.epsilon_2_end = checkpoint->number("creep.epsilon_2_end");
      creep.epsilon_v_end = checkpoint->number("creep.epsilon_v_end");
      creep.equilibrium.reached = checkpoint->flag("creep.reached");
      creep.equilibrium.aborted = checkpoint->flag("creep.aborted");
      creep.equilibrium.steps = checkpoint->count("creep.hold_steps");
      creep.equilibrium.report = checkpoint->report("creep.report");
    }
  }
  protocols::RunGuard guard(s.guard, "creep");
  const auto build = [&](const Engine& e, const protocols::Cursor& cursor) {
    protocols::Checkpoint c = checkpoint_head(invocation, e, cursor, input_checksum,
                                              wall_before + progress.elapsed_seconds());
    c.set_count("output.csv.bytes", csv.text().size());
    if (cursor.phase >= hold_phase) c.set_number("creep.q_hold", q_hold);
    if (cursor.phase == resumed_src_phase) {
      c.set_number("creep.epsilon_2_switch", creep.epsilon_2_switch);
      c.set_number("creep.epsilon_v_switch", creep.epsilon_v_switch);
      c.set_number("creep.epsilon_2_end", creep.epsilon_2_end);
      c.set_number("creep.epsilon_v_end", creep.epsilon_v_end);
      c.set_flag("creep.reached", creep.equilibrium.reached);
      c.set_flag("creep.aborted", creep.equilibrium.aborted);
      c.set_count("creep.hold_steps", creep.equilibrium.steps);
      c.set_report("creep.report", creep.equilibrium.report);
    }
    return c;
  };
  guard.on_write([&] { csv.flush(); });
  const protocols::LoopHooks hooks = guard_hooks(guard, build);
  // The control of one phase: fresh, or resumed when the checkpoint stopped in it.
  const auto control_of = [&](int p) {
    protocols::LoopControl c{hooks, protocols::Cursor{}, checkpoint && resume_cursor.phase == p};
    if (c.resume) c.cursor = resume_cursor;
    c.cursor.phase = p;
    return c;
  };

  const auto on_record = [&](const Engine& e, const Configuration& st) {
    record(st);
    char detail[96];
    std::snprintf(detail, sizeof detail, "SRC epsilon_2 %.5f  q %.4f", protocols::axial_strain(e),
                  protocols::deviator_ratio(e));
    progress.update(static_cast<double>(e.step_count()), detail);
    return true;
  };
  Configuration state;
  engine.export_to(state);
  if (!checkpoint) {
    guard.check(engine);
    record(state);
  }
  // Phase 0: SRC up to the chosen strain, or until q first reaches the chosen value.
  if (phase == src_phase) {
    const double switch_strain = s.at_epsilon_2.value_or(s.epsilon_2_max);
    protocols::StepCondition reached_q;
    if (s.at_q) {
      reached_q = [&](const Engine& e) { return protocols::deviator_ratio(e) >= *s.at_q; };
    }
    const auto src = protocols::run_strain_rate(engine, s.src, switch_strain, pressure, state,
                                                on_record, reached_q, control_of(src_phase));
    if (s.at_q && !src.stopped) {
      engine.export_to(state);
      csv.flush();
      guard.finish();
      throw std::runtime_error("creep: q never reached at_q = " + std::to_string(*s.at_q) +
                               " before epsilon_2_max = " + std::to_string(s.epsilon_2_max) +
                               " (the SRC series is in " + s.csv.string() + ")");
    }
    // q_hold is the chosen q, or the (contact-stress) q at the chosen strain.
    q_hold = s.at_q.value_or(protocols::deviator_ratio(engine));
    phase = hold_phase;
  }
  // Phase 1: hold.
  const auto on_check = [&](const Engine& e, const Configuration& st, const EquilibriumReport& r) {
    record(st);
    char detail[128];
    std::snprintf(detail, sizeof detail, "hold q %.4f  epsilon_2 %.5f  max force %.3g", q_hold,
                  protocols::axial_strain(e), r.max_net_force);
    progress.update(static_cast<double>(e.step_count()), detail);
    return true;
  };
  if (phase == hold_phase) {
    creep = protocols::hold_deviator(engine, q_hold, pressure, s.creep, state, on_check,
                                     control_of(hold_phase));
    if (s.hold_sample && creep.equilibrium.reached) write_configuration(state, *s.hold_sample);
    if (s.resume && creep.equilibrium.reached) phase = resumed_src_phase;
  }
  // Phase 2: optionally resume SRC to epsilon_2_max.
  if (phase == resumed_src_phase) {
    protocols::run_strain_rate(engine, s.src, s.epsilon_2_max, pressure, state, on_record, {},
                               control_of(resumed_src_phase));
  }
  const double wall_seconds = wall_before + progress.elapsed_seconds();
  progress.finish();
  engine.export_to(state);
  csv.flush();
  if (s.final_sample) write_configuration(state, *s.final_sample);

  protocols::JsonObject summary;
  summary.add("command", "creep")
      .add("settings", invocation.settings)
      .add("input", s.input.string())
      .add("mu", s.material.mu)
      .add("gamma", s.src.gamma)
      .add("trigger", s.at_q ? "q" : "epsilon_2")
      .add("q_hold", q_hold)
      .add("epsilon_2_switch", creep.epsilon_2_switch)
      .add("epsilon_v_switch", creep.epsilon_v_switch)
      .add("epsilon_2_equilibrium", creep.epsilon_2_end)
      .add("epsilon_v_equilibrium", creep.epsilon_v_end)
      .add("delta_epsilon_2", creep.delta_epsilon_2())
      .add("delta_epsilon_v", creep.delta_epsilon_v())
      .add("reached_equilibrium", creep.equilibrium.reached)
      .add("hold_steps", creep.equilibrium.steps)
      .add("hold_time", static_cast<double>(creep.equilibrium.steps) * engine.dt())
      .add("equilibrium",
           protocols::equilibrium_json(creep.equilibrium.report, s.creep.equilibration.tolerances))
      .add("resumed", s.resume && creep.equilibrium.reached)
      .add("steps", engine.step_count() - s.sample.step)
      .add("wall_seconds", wall_seconds)
      .add("csv", s.csv.string());
  protocols::write_json(s.summary, summary);
  guard.finish();
  if (!creep.equilibrium.reached) {
    throw std::runtime_error(std::string("creep: no equilibrium at q = ") + std::to_string(q_hold) +
                             (creep.equilibrium.aborted
                                  ? " (the strain guard fired: the sample flows)"
                                  : " within equilibrium.max_steps"));
  }
}

void add_creep_command(CLI::App& app) {
  auto options = std::make_shared<CreepCommandOptions>();
  auto* cmd =
      app.add_subcommand("creep",
                         "SRC test switched to stress control at a chosen strain or q, held to "
                         "equilibrium; records the creep strain (SPEC §3.4)");
  cmd->add_option("CONFIG", options->settings, "settings (TOML, docs/protocols.md)")->required();
  cmd->add_option("--set", options->overrides, "override a setting, key=value");
  cmd->add_flag("--quiet", options->quiet, "no progress on stderr");
  cmd->callback([options] {
    run_creep(protocols::Invocation::start("creep", options->settings, options->overrides),
              options->quiet, nullptr);
  });
}

}  // namespace granstab::cli
