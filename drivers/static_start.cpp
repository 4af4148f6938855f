#include "static_start.hpp"

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "common/io/configuration_file.hpp"
#include "common/io/json_text.hpp"
#include "common/progress.hpp"
#include "common/start_state.hpp"
#include "stability_probe.hpp"
#include "static/network.hpp"

namespace granstab::cli {

MaterialOverrides StaticStartOptions::overrides() const {
  MaterialOverrides o;
  for (const std::string& s : material_settings) o.set.push_back(parse_material_setting(s));
  o.kt_ratio = kt_ratio;
  o.mu = mu;
  o.clip_to_cone = clip_to_cone;
  return o;
}

void add_static_start_options(CLI::App& cmd, StaticStartOptions& o, bool with_set) {
  cmd.add_option("--mu", o.mu, "friction of the biaxial stage (default: the sample's material.mu)")
      ->check(CLI::NonNegativeNumber);
  cmd.add_option("--kt-ratio", o.kt_ratio,
                 "K_T / K_N of the biaxial stage; the stored tangential displacements are "
                 "rescaled so that the start's tangential forces are unchanged")
      ->check(CLI::PositiveNumber);
  if (with_set)
    cmd.add_option("--set", o.material_settings,
                   "material.KEY=VALUE (KEY: k_n, k_t, mu, zeta, mu_wall), applied before "
                   "--kt-ratio and --mu");
  cmd.add_flag("--clip-to-cone", o.clip_to_cone,
               "move contacts whose |F_T| exceeds the new mu F_N onto the cone instead of "
               "refusing the start");
  cmd.add_flag("--polish", o.polish,
               "accept a start out of equilibrium (SPEC 3.1): move it to equilibrium first and "
               "report how far");
  cmd.add_flag("--quiet", o.quiet, "no progress on stderr");
}

void split_material_settings(std::vector<std::string>& settings, StaticStartOptions& o) {
  std::vector<std::string> rest;
  for (std::string& s : settings)
    (s.rfind("material.", 0) == 0 ? o.material_settings : rest).push_back(std::move(s));
  settings = std::move(rest);
}

StaticStart read_static_start(const std::string& path, const StaticStartOptions& options,
                              const std::function<void(const Configuration&)>& require) {
  StaticStart out;
  out.config = read_configuration(path);
  try {
    out.material = apply_material_overrides(out.config, options.overrides());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());
  }
  if (out.material.clipped > 0 && !options.quiet)
    std::cerr << path << ": " << out.material.clipped
              << " contacts moved onto the Coulomb cone (--clip-to-cone)\n";
  if (require) require(out.config);
  validate_start_state(out.config, path, options.polish);
  if (!options.polish) return out;

  // The polish of the static solver (§S3.0) on the biaxial start's loads, then back to a
  // configuration, so that every method of the command starts from the same polished state.
  statics::Network net = statics::network_from_configuration(out.config);
  net.constraints.cell_free = {true, true};
  net.constraints.remove_rattlers = true;
  net.loading.sigma = out.config.stage.sigma_ext;
  out.polish = statics::polish_start(net, statics::SolverOptions{});
  out.config = crosscheck::configuration_of_static_state(net, out.config);
  const StartStateReport after = check_start_state(out.config);
  if (!options.quiet) {
    char line[320];
    std::snprintf(line, sizeof line,
                  "%s: polished to equilibrium: disks moved by at most %.3g a (disk %zu), "
                  "rotated by at most %.3g rad, cell strained by at most %.3g; relative "
                  "residual %.3g -> %.3g%s\n",
                  path.c_str(), out.polish->max_displacement, out.polish->max_displacement_disk,
                  out.polish->max_rotation, out.polish->max_strain, out.polish->residual_before,
                  out.polish->residual_after,
                  after.equilibrium.in_equilibrium ? "" : " (still outside SPEC 3.1)");
    std::cerr << line;
  }
  return out;
}

std::function<void(const statics::StepProgress&)> static_progress(std::string label, bool enabled,
                                                                  double target,
                                                                  std::string target_name) {
  if (!enabled && !has_progress_observer()) return {};
  struct State {
    std::unique_ptr<Progress> progress;
    double load0 = NAN;
  };
  auto state = std::make_shared<State>();
  state->progress = std::make_unique<Progress>(label, 0.0, enabled);
  return [state, target, basis = "rate so far, to " + target_name](const statics::StepProgress& p) {
    if (std::isnan(state->load0)) state->load0 = p.load;
    const double elapsed = state->progress->elapsed_seconds();
    std::optional<double> left;
    if (std::isfinite(target) && p.load > state->load0 && target > p.load)
      left = elapsed * (target - p.load) / (p.load - state->load0);
    char detail[200];
    std::snprintf(detail, sizeof detail, "q %.6g  states %d  attempts %d  sliding %d  %.3g s/state",
                  p.load, p.states, p.attempts, p.n_sliding,
                  p.states > 0 ? elapsed / p.states : 0.0);
    if (p.finished) {
      state->progress->finish(detail);  // a run shorter than the line interval shows a line too
    } else {
      state->progress->update_estimated(p.states, left, std::isfinite(target) ? basis : "", detail);
    }
  };
}

std::string static_start_json(const StaticStart& start, const std::string& indent) {
  std::string s = indent + "\"material\": " + material_json(start.config.material) + ",\n" +
                  indent + "\"clipped_to_cone\": " + std::to_string(start.material.clipped) +
                  ",\n" + indent + "\"start_polish\": ";
  if (!start.polish) return s + "null";
  const statics::StartPolish& p = *start.polish;
  return s + "{\"max_displacement\": " + json_number(p.max_displacement) +
         ", \"max_displacement_disk\": " + std::to_string(p.max_displacement_disk) +
         ", \"max_rotation\": " + json_number(p.max_rotation) +
         ", \"max_strain\": " + json_number(p.max_strain) +
         ", \"residual_before\": " + json_number(p.residual_before) +
         ", \"residual_after\": " + json_number(p.residual_after) + "}";
}

}  // namespace granstab::cli

namespace granstab::cli {

void add_md_wait_options(CLI::App& cmd, protocols::EquilibrationOptions& wait,
                         double& epsilon_2_max) {
  cmd.add_option("--force-tolerance", wait.tolerances.force,
                 "dynamic SPEC 3.1 net-force tolerance (units of aP)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd.add_option("--torque-tolerance", wait.tolerances.torque,
                 "dynamic SPEC 3.1 net-torque tolerance (units of a^2 P)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd.add_option("--stress-tolerance", wait.tolerances.stress,
                 "dynamic SPEC 3.1 relative stress tolerance")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd.add_option("--max-steps-per-increment", wait.max_steps,
                 "MD steps allowed to reach equilibrium after one increment")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd.add_option("--epsilon-2-max", epsilon_2_max,
                 "an MD wait stops when epsilon_2 exceeds this (the sample flows)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
}

void add_hill_option(CLI::App& cmd, std::size_t& hill_every) {
  cmd.add_option_function<std::string>(
         "--hill",
         [&hill_every](const std::string& v) {
           if (v == "every") {
             hill_every = 1;
           } else if (v == "off") {
             hill_every = 0;
           } else {
             std::size_t used = 0;
             long long n = -1;
             try {
               n = std::stoll(v, &used);
             } catch (const std::exception&) {
             }
             if (used != v.size() || n < 1)
               throw CLI::ValidationError("--hill",
                                          v + ": expected every, off or a positive stride");
             hill_every = static_cast<std::size_t>(n);
           }
         },
         "Hill indicator (smallest eigenvalue of the symmetric part) in the curve: every state, "
         "every N-th state, or off (default: every " +
             std::to_string(hill_every) + "th; an indicator only, the path does not depend on it)")
      ->type_name("every|N|off");
  cmd.add_flag_callback(
      "--no-hill", [&hill_every] { hill_every = 0; }, "the same as --hill off");
}

void add_step_control_option(CLI::App& cmd, statics::Q1Options& options) {
  cmd.add_option_function<std::string>(
         "--steps",
         [&options](const std::string& v) {
           options.steps =
               v == "fixed" ? statics::StepControl::fixed : statics::StepControl::adaptive;
         },
         std::string("step control: adaptive (steps up to --max-step-factor dq while no contact "
                     "changes status, rows at the multiples of dq interpolated inside them) or "
                     "fixed (steps of dq) (default: ") +
             statics::step_control_name(options.steps) + ")")
      ->type_name("adaptive|fixed")
      ->check(CLI::IsMember({"adaptive", "fixed"}));
  cmd.add_option("--max-step-factor", options.max_step_factor,
                 "adaptive steps: the largest step in units of dq")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1e6));
}

}  // namespace granstab::cli
