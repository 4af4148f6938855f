#pragma once
// The start of every static run (q1, compare, probe; issue #19): the sample read, its biaxial
// material set (--mu, --kt-ratio, --set material.KEY=VALUE), validated (common/start_state.hpp)
// and, with --polish, moved to equilibrium first; and the progress lines of the stepping.
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/configuration.hpp"
#include "common/material_override.hpp"
#include "dynamic/protocols/equilibration.hpp"
#include "static/q1.hpp"

namespace CLI {
class App;
}

namespace granstab::cli {

struct StaticStartOptions {
  std::optional<double> mu, kt_ratio;
  std::vector<std::string> material_settings;  // "material.KEY=VALUE"
  bool clip_to_cone = false;
  bool polish = false;
  bool quiet = false;

  MaterialOverrides overrides() const;
};

// --hill every|N|off and its alias --no-hill (= off): the stride of the Hill indicator in the
// static curve (Q1Options::hill_every), shared by q1 and compare.
void add_hill_option(CLI::App& cmd, std::size_t& hill_every);

// --steps adaptive|fixed and --max-step-factor X: the step control of the static stepping
// (Q1Options::steps, max_step_factor), shared by q1, compare and sic.
void add_step_control_option(CLI::App& cmd, statics::Q1Options& options);

// --force-tolerance, --torque-tolerance, --stress-tolerance (SPEC §3.1), --max-steps-per-increment
// and --epsilon-2-max: the MD waits of the SIC increments that compare and sic run.
void add_md_wait_options(CLI::App& cmd, protocols::EquilibrationOptions& wait,
                         double& epsilon_2_max);

// --mu, --kt-ratio, --clip-to-cone, --polish, --quiet; and --set material.KEY=VALUE when
// `with_set` (compare shares its --set with the dynamic settings: it passes the material.* ones
// on with split_material_settings).
void add_static_start_options(CLI::App& cmd, StaticStartOptions& options, bool with_set);

// Moves the material.* entries of `settings` into options.material_settings.
void split_material_settings(std::vector<std::string>& settings, StaticStartOptions& options);

struct StaticStart {
  Configuration config;
  MaterialOverrideReport material;
  std::optional<statics::StartPolish> polish;  // with --polish
};

// Reads `path`, applies the material options, validates the start (throws std::invalid_argument
// naming the file and the disk or contact) and polishes it with --polish. Notes on stderr what
// was clipped or polished. Nothing is written: callers validate before creating any output.
// `require` (optional) checks what the command itself needs of the sample before the generic
// validation (compare: an isotropic stress-controlled stage), so that its message comes first.
StaticStart read_static_start(const std::string& path, const StaticStartOptions& options,
                              const std::function<void(const Configuration&)>& require = {});

// Progress lines of a static run on stderr (common/progress.hpp) every 2 s: the load, states,
// attempts, sliding contacts, time per state, and an ETA towards `target` (named target_name:
// --q-max, or the rigid-limit bound of q1) when finite. Empty when disabled.
std::function<void(const statics::StepProgress&)> static_progress(std::string label, bool enabled,
                                                                  double target,
                                                                  std::string target_name);

// "material": {...}, "start_polish": {...} | null: the JSON fields q1.json and compare.json share.
std::string static_start_json(const StaticStart& start, const std::string& indent);

}  // namespace granstab::cli
