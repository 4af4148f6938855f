// granstab biaxial CONFIG.toml: biaxial compression of a prepared sample (SPEC §3.3), strain-rate
// controlled (SRC) or by stress increments with equilibrium after each (SIC). Writes a CSV of
// every SPEC §2 quantity, a JSON summary, the final state and states at chosen strains / q.
// Settings: docs/protocols.md.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "common/io/configuration_file.hpp"
#include "common/io/csv_writer.hpp"
#include "common/measurements.hpp"
#include "common/progress.hpp"
#include "common/run_config.hpp"
#include "dynamic/protocols/biaxial.hpp"
#include "dynamic/protocols/json_summary.hpp"
#include "dynamic/protocols/record.hpp"
#include "dynamic/protocols/settings.hpp"
#include "dynamic/protocols/snapshots.hpp"

namespace granstab::cli {
namespace {

struct BiaxialOptions {
  std::string settings;
  std::vector<std::string> overrides;
  bool quiet = false;
};

struct BiaxialSettings {
  std::filesystem::path input;
  Configuration sample;
  Material material;
  bool strain_rate = true;
  protocols::StrainRateOptions src;
  double epsilon_2_max = 0.02;
  protocols::StressStepOptions sic;
  StressMeasure measure = StressMeasure::cauchy;
  EngineOptions engine;
  std::filesystem::path csv, summary;
  std::optional<std::filesystem::path> final_sample;
  double save_every = 0.0;
  std::filesystem::path save_prefix;
  protocols::SnapshotSettings snapshots;
};

BiaxialSettings read_settings(const BiaxialOptions& o) {
  RunConfig rc = RunConfig::from_file(o.settings, o.overrides);
  BiaxialSettings s;
  s.input = protocols::existing_file(rc, "input.sample");
  s.sample = read_configuration(s.input);
  s.material = protocols::read_material(rc, s.sample.material);
  s.strain_rate =
      rc.choice("biaxial.control", "strain-rate", {"strain-rate", "stress-steps"}) == "strain-rate";
  if (s.strain_rate) {
    s.src.gamma = rc.number("biaxial.gamma", 1e-4, 1e-12, 1.0);
    s.epsilon_2_max = rc.number("biaxial.epsilon_2_max", 0.02, 1e-12, 0.9);
    s.src.record_interval = rc.number("biaxial.record_interval", 1e-4, 1e-12, 1.0);
  } else {
    s.sic.delta_q = rc.number("biaxial.delta_q", 1e-2, 1e-9, 10.0);
    s.sic.q_max = rc.number("biaxial.q_max", 1.0, 0.0, 100.0);
    s.sic.epsilon_2_max = rc.number("biaxial.failure_epsilon_2", 0.2, 1e-9, 0.9);
    s.sic.equilibration = protocols::read_equilibration(rc);
  }
  s.measure = rc.choice("biaxial.measure", "cauchy", {"cauchy", "nominal"}) == "nominal"
                  ? StressMeasure::nominal
                  : StressMeasure::cauchy;
  s.engine = protocols::read_engine_options(rc);
  s.csv = protocols::required_path(rc, "output.csv");
  s.summary = rc.path("output.summary").value_or(std::filesystem::path(s.csv).replace_extension(".json"));
  s.final_sample = rc.path("output.sample");
  s.save_every = rc.number("output.save_every", 0.0, 0.0, 100.0);
  s.save_prefix = rc.path("output.save_prefix").value_or(std::filesystem::path(s.csv).replace_extension(""));
  s.snapshots = protocols::read_snapshot_settings(rc);
  rc.finish();
  return s;
}

// Saved states are named by the strain (SRC) or q (SIC) they were saved at.
std::filesystem::path saved_state_name(const std::filesystem::path& prefix, const char* what,
                                       double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "_%s%.6f.granstab", what, value);
  return prefix.string() + buf;
}

void run_biaxial(const BiaxialOptions& o) {
  const BiaxialSettings s = read_settings(o);  // every settings error comes before any output
  constexpr double pressure = 1.0;             // units: P = 1
  Engine engine(s.sample, s.engine);
  protocols::begin_biaxial_stage(engine, s.material, pressure);
  engine.set_measure(s.measure);

  std::vector<std::string> columns = protocols::state_columns();
  if (!s.strain_rate) {
    for (const char* c : {"q_target", "increment_steps", "reached", "stress_error_1",
                          "stress_error_2"}) {
      columns.emplace_back(c);
    }
  }
  CsvWriter csv(s.csv, columns, 30.0);
  protocols::SnapshotWriter snapshots(s.snapshots);
  std::vector<std::string> saved;
  double next_save = s.save_every;
  double largest_sigma_1_error = 0.0, largest_x_s = 0.0;
  Configuration state;
  protocols::JsonObject summary;
  summary.add("command", "biaxial").add("settings", o.settings).add("input", s.input.string());
  protocols::JsonObject material;
  material.add("kappa", s.material.kappa())
      .add("kt_over_kn", s.material.kt_over_kn())
      .add("mu", s.material.mu)
      .add("mu_prep", s.sample.material.mu)
      .add("zeta", s.material.zeta)
      .add("mu_wall", s.material.mu_wall);
  summary.add("material", material);
  std::string stop_reason;
  double wall_seconds = 0.0;

  if (s.strain_rate) {
    Progress progress("biaxial SRC", s.epsilon_2_max, !o.quiet);
    engine.export_to(state);
    const auto record = [&](const Engine& e, const Configuration& st) {
      const Measurements m = measure(st);
      csv.row(protocols::state_row(st, m));
      largest_sigma_1_error = std::max(largest_sigma_1_error, std::abs(m.sigma[0][0] - pressure));
      if (s.save_every > 0.0 && m.epsilon_2 >= next_save * (1.0 - 1e-9)) {
        const auto name = saved_state_name(s.save_prefix, "e2_", next_save);
        write_configuration(st, name);
        saved.push_back(name.string());
        next_save = (std::floor(m.epsilon_2 / s.save_every + 1e-9) + 1.0) * s.save_every;
      }
      snapshots.maybe_write(st, e.step_count());
      char detail[96];
      std::snprintf(detail, sizeof detail, "q %.4f  epsilon_v %.5f", m.q, m.epsilon_v);
      progress.update(m.epsilon_2, detail);
      return true;
    };
    record(engine, state);
    const auto result = protocols::run_strain_rate(engine, s.src, s.epsilon_2_max, pressure,
                                                   state, record);
    stop_reason = result.stopped ? "stopped" : "epsilon_2_max";
    wall_seconds = progress.elapsed_seconds();
    progress.finish();
    summary.add("control", "strain-rate")
        .add("gamma", s.src.gamma)
        .add("epsilon_2_max", s.epsilon_2_max)
        .add("record_interval", s.src.record_interval)
        .add("largest_sigma_1_error", largest_sigma_1_error);
  } else {
    Progress progress("biaxial SIC", s.sic.q_max, !o.quiet);
    const auto on_equilibrium = [&](const Engine& e, const Configuration& st,
                                    const protocols::StressStepRecord& r) {
      const Measurements m = measure(st);
      std::vector<double> row = protocols::state_row(st, m);
      row.insert(row.end(), {r.q_target, static_cast<double>(r.steps),
                             r.equilibrium.reached ? 1.0 : 0.0, r.equilibrium.report.stress_error[0],
                             r.equilibrium.report.stress_error[1]});
      csv.row(row);
      if (!r.equilibrium.reached) return;
      largest_x_s = std::max(largest_x_s, m.x_s);
      if (s.save_every > 0.0 && r.q_target >= next_save * (1.0 - 1e-9)) {
        const auto name = saved_state_name(s.save_prefix, "q_", r.q_target);
        write_configuration(st, name);
        saved.push_back(name.string());
        next_save = (std::floor(r.q_target / s.save_every + 1e-9) + 1.0) * s.save_every;
      }
      snapshots.maybe_write(st, e.step_count());
    };
    const auto on_check = [&](const Engine& e, const Configuration&, const EquilibriumReport& r) {
      char detail[128];
      std::snprintf(detail, sizeof detail, "epsilon_2 %.5f  max force %.3g  stress err %.3g",
                    protocols::axial_strain(e), r.max_net_force,
                    std::max(r.stress_error[0], r.stress_error[1]));
      progress.update(e.stage().sigma_ext[1] / pressure - 1.0, detail);
      return true;
    };
    const auto result =
        protocols::run_stress_steps(engine, s.sic, pressure, state, on_equilibrium, on_check);
    stop_reason = result.stop_reason;
    wall_seconds = progress.elapsed_seconds();
    progress.finish();
    summary.add("control", "stress-steps")
        .add("delta_q", s.sic.delta_q)
        .add("q_max", s.sic.q_max)
        .add("equilibrium_increments", static_cast<std::int64_t>(result.increments))
        .add("q_last_equilibrium", result.increments * s.sic.delta_q)
        .add("largest_x_s_in_equilibrium", largest_x_s);
  }

  engine.export_to(state);
  csv.flush();
  if (s.final_sample) write_configuration(state, *s.final_sample);
  snapshots.write_final(state);
  summary.add("measure", s.measure == StressMeasure::nominal ? "nominal" : "cauchy")
      .add("stop_reason", stop_reason)
      .add("dt", engine.dt())
      .add("steps", engine.step_count() - s.sample.step)
      .add("wall_seconds", wall_seconds)
      .add("rows", static_cast<std::uint64_t>(csv.rows()))
      .add("csv", s.csv.string())
      .add("final", protocols::measurements_json(measure(state)));
  std::string saved_list;
  for (const auto& name : saved) saved_list += (saved_list.empty() ? "" : ";") + name;
  summary.add("saved_states", saved_list);
  protocols::write_json(s.summary, summary);
}

}  // namespace

void add_biaxial_command(CLI::App& app) {
  auto options = std::make_shared<BiaxialOptions>();
  auto* cmd = app.add_subcommand(
      "biaxial", "Biaxial compression at sigma_1 = P: strain-rate controlled (SRC) or by stress "
                 "increments with equilibrium after each (SIC) (SPEC §3.3)");
  cmd->add_option("CONFIG", options->settings, "settings (TOML, docs/protocols.md)")->required();
  cmd->add_option("--set", options->overrides, "override a setting, key=value");
  cmd->add_flag("--quiet", options->quiet, "no progress on stderr");
  cmd->callback([options] { run_biaxial(*options); });
}

}  // namespace granstab::cli
