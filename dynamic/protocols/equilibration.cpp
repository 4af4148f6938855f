#include "equilibration.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/measurements.hpp"

namespace granstab::protocols {

EquilibriumReport check_loaded_equilibrium(const Configuration& state,
                                           const EquilibriumTolerances& tolerances,
                                           std::span<const double> external_fx,
                                           std::span<const double> external_fy) {
  EquilibriumReport report = check_equilibrium(state, tolerances);
  if (external_fx.empty() && external_fy.empty()) return report;
  const std::size_t n = state.disks.size();
  if (external_fx.size() != n || external_fy.size() != n) {
    throw std::invalid_argument("equilibrium check: external forces need N entries per component");
  }
  const auto loads = contact_loads(state);
  const NetForces net = net_forces(state, loads);
  const auto rattler = find_rattlers(state, loads);
  double largest = 0.0, sum2 = 0.0;
  std::size_t where = 0, counted = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (rattler[i]) continue;
    const double f = std::hypot(net.fx[i] + external_fx[i], net.fy[i] + external_fy[i]);
    sum2 += f * f;
    ++counted;
    if (f > largest) {
      largest = f;
      where = i;
    }
  }
  report.max_net_force = largest;
  report.max_force_disk = where;
  report.f_2 = counted ? std::sqrt(sum2 / static_cast<double>(counted)) : 0.0;
  report.force_ok = largest < tolerances.force;
  report.in_equilibrium = report.force_ok && report.torque_ok && report.stress_ok;
  return report;
}

EquilibrationResult run_to_equilibrium(Engine& engine, const EquilibrationOptions& options,
                                       Configuration& state, const EquilibrationObserver& observer,
                                       std::span<const double> external_fx,
                                       std::span<const double> external_fy,
                                       const LoopControl& control) {
  if (options.check_interval == 0) {
    throw std::invalid_argument("equilibrium.check_interval must be >= 1");
  }
  EquilibrationResult result;
  Cursor cursor = control.cursor;
  // A resumed wait continues after a check that its observer saw and that let it go on.
  bool checked = control.resume;
  if (checked) result.steps = cursor.steps;
  for (;;) {
    if (!checked) {
      control.check(engine);
      engine.export_to(state);
      result.report = check_loaded_equilibrium(state, options.tolerances, external_fx, external_fy);
      const bool go_on = !observer || observer(engine, state, result.report);
      if (result.report.in_equilibrium) {
        result.reached = true;
        return result;
      }
      if (!go_on) {
        result.aborted = true;
        return result;
      }
      if (result.steps >= options.max_steps) return result;
      cursor.steps = result.steps;
      control.safe_point(engine, cursor);
    } else if (result.steps >= options.max_steps) {
      engine.export_to(state);
      result.report = check_loaded_equilibrium(state, options.tolerances, external_fx, external_fy);
      return result;
    }
    checked = false;
    const std::uint64_t chunk = std::min(options.check_interval, options.max_steps - result.steps);
    engine.run(chunk);
    result.steps += chunk;
  }
}

}  // namespace granstab::protocols
