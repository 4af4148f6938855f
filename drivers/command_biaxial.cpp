// granstab biaxial CONFIG.toml: biaxial compression of a prepared sample (SPEC §3.3), strain-rate
// controlled (SRC) or by stress increments with equilibrium after each (SIC). Writes a CSV of
// every SPEC §2 quantity, a JSON summary, the final state and states at chosen strains / q.
// Settings: docs/protocols.md.
#include <CLI/CLI.hpp>
#include <chrono>
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
  protocols::GuardSettings guard;
};

BiaxialSettings read_biaxial_settings(const protocols::Invocation& invocation) {
  RunConfig rc = invocation.settings_config();
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
  s.summary =
      rc.path("output.summary").value_or(std::filesystem::path(s.csv).replace_extension(".json"));
  s.final_sample = rc.path("output.sample");
  s.save_every = rc.number("output.save_every", 0.0, 0.0, 100.0);
  s.save_prefix =
      rc.path("output.save_prefix").value_or(std::filesystem::path(s.csv).replace_extension(""));
  s.snapshots = protocols::read_snapshot_settings(rc);
  s.guard = protocols::read_guard_settings(
      rc, std::filesystem::path(s.csv).replace_extension(".checkpoint"));
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

// Saved state names are kept one a line in checkpoints.
std::string join_lines(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += n + "\n";
  return out;
}

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> names;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) break;
    names.push_back(text.substr(pos, end - pos));
    pos = end + 1;
  }
  return names;
}

}  // namespace

void run_biaxial(const protocols::Invocation& invocation, bool quiet,
                 const protocols::Checkpoint* checkpoint) {
  // Settings errors come before any output.
  const BiaxialSettings s = read_biaxial_settings(invocation);
  constexpr double pressure = 1.0;  // units: P = 1
  const std::string input_checksum = protocols::file_checksum(s.input);
  if (checkpoint) require_same_input(*checkpoint, s.input.string(), input_checksum);
  const auto started = std::chrono::steady_clock::now();
  const double wall_before = checkpoint ? checkpoint->number("run.wall_seconds") : 0.0;
  Engine engine(checkpoint ? checkpoint->configuration("engine") : s.sample, s.engine);
  if (!checkpoint) {
    protocols::begin_biaxial_stage(engine, s.material, pressure);
    engine.set_measure(s.measure);
  }

  std::vector<std::string> columns = protocols::state_columns();
  if (!s.strain_rate) {
    for (const char* c :
         {"q_target", "increment_steps", "reached", "stress_error_1", "stress_error_2"}) {
      columns.emplace_back(c);
    }
  }
  CsvWriter csv(s.csv, columns, 30.0);
  protocols::SnapshotWriter snapshots(s.snapshots);
  std::vector<std::string> saved;
  double next_save = s.save_every;
  double largest_sigma_1_error = 0.0, largest_x_s = 0.0;
  protocols::LoopControl control;
  if (checkpoint) {
    protocols::restore_csv(csv, checkpoint->count("output.csv.bytes"));
    snapshots.restore(checkpoint->has("output.vtk.next")
                          ? std::optional(checkpoint->count("output.vtk.next"))
                          : std::nullopt,
                      checkpoint->count("output.vtk.written"));
    saved = split_lines(checkpoint->text("biaxial.saved"));
    next_save = checkpoint->number("biaxial.next_save");
    largest_sigma_1_error = checkpoint->number("biaxial.largest_sigma_1_error");
    largest_x_s = checkpoint->number("biaxial.largest_x_s");
    control.cursor = protocols::get_cursor(*checkpoint);
    control.resume = true;
  }
  protocols::RunGuard guard(s.guard, s.strain_rate ? "biaxial SRC" : "biaxial SIC");
  const auto build = [&](const Engine& e, const protocols::Cursor& cursor) {
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    protocols::Checkpoint c =
        checkpoint_head(invocation, e, cursor, input_checksum, wall_before + elapsed);
    c.set_count("output.csv.bytes", csv.text().size());
    if (snapshots.next_step()) c.set_count("output.vtk.next", *snapshots.next_step());
    c.set_count("output.vtk.written", snapshots.written());
    c.set("biaxial.saved", join_lines(saved));
    c.set_number("biaxial.next_save", next_save);
    c.set_number("biaxial.largest_sigma_1_error", largest_sigma_1_error);
    c.set_number("biaxial.largest_x_s", largest_x_s);
    return c;
  };
  guard.on_write([&] { csv.flush(); });
  control.hooks = guard_hooks(guard, build);
  Configuration state;
  protocols::JsonObject summary;
  summary.add("command", "biaxial")
      .add("settings", invocation.settings)
      .add("input", s.input.string());
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
    Progress progress("biaxial SRC", s.epsilon_2_max, !quiet);
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
    if (!checkpoint) record(engine, state);  // a resumed CSV has the first row already
    const auto result = protocols::run_strain_rate(engine, s.src, s.epsilon_2_max, pressure, state,
                                                   record, {}, control);
    stop_reason = result.stopped ? "stopped" : "epsilon_2_max";
    wall_seconds = wall_before + progress.elapsed_seconds();
    progress.finish();
    summary.add("control", "strain-rate")
        .add("gamma", s.src.gamma)
        .add("epsilon_2_max", s.epsilon_2_max)
        .add("record_interval", s.src.record_interval)
        .add("largest_sigma_1_error", largest_sigma_1_error);
  } else {
    Progress progress("biaxial SIC", s.sic.q_max, !quiet);
    const auto on_equilibrium = [&](const Engine& e, const Configuration& st,
                                    const protocols::StressStepRecord& r) {
      const Measurements m = measure(st);
      std::vector<double> row = protocols::state_row(st, m);
      row.insert(row.end(),
                 {r.q_target, static_cast<double>(r.steps), r.equilibrium.reached ? 1.0 : 0.0,
                  r.equilibrium.report.stress_error[0], r.equilibrium.report.stress_error[1]});
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
    const auto result = protocols::run_stress_steps(engine, s.sic, pressure, state, on_equilibrium,
                                                    on_check, control);
    stop_reason = result.stop_reason;
    wall_seconds = wall_before + progress.elapsed_seconds();
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
  guard.finish();
}

void add_biaxial_command(CLI::App& app) {
  auto options = std::make_shared<BiaxialOptions>();
  auto* cmd = app.add_subcommand(
      "biaxial",
      "Biaxial compression at sigma_1 = P: strain-rate controlled (SRC) or by stress "
      "increments with equilibrium after each (SIC) (SPEC §3.3)");
  cmd->add_option("CONFIG", options->settings, "settings (TOML, docs/protocols.md)")->required();
  cmd->add_option("--set", options->overrides, "override a setting, key=value");
  cmd->add_flag("--quiet", options->quiet, "no progress on stderr");
  cmd->callback([options] {
    run_biaxial(protocols::Invocation::start("biaxial", options->settings, options->overrides),
                options->quiet, nullptr);
  });
}

}  // namespace granstab::cli
