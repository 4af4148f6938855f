#include "sanity.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/measurements.hpp"

namespace granstab::dynamic {
namespace {

std::string at_step(const Engine& engine) {
  return "step " + std::to_string(engine.step_count()) + ": ";
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

std::optional<std::string> find_blow_up(const Engine& engine, const Configuration& exported,
                                        const SanityLimits& limits) {
  const auto length = engine.length(), rate = engine.length_rate();
  for (int a = 0; a < 2; ++a) {
    if (!std::isfinite(length[a]) || !(length[a] > 0.0) || !std::isfinite(rate[a])) {
      return at_step(engine) + "cell axis " + std::to_string(a + 1) + ": L = " + number(length[a]) +
             ", dL/dt = " + number(rate[a]) + " (not finite or not > 0)";
    }
  }
  const auto x = engine.x(), y = engine.y(), vx = engine.vx(), vy = engine.vy();
  const auto omega = engine.omega();
  const std::size_t n = engine.size();
  for (std::size_t i = 0; i < n; ++i) {
    const struct {
      const char* name;
      double value;
    } fields[] = {{"x", x[i]},
                  {"y", y[i]},
                  {"vx", vx[i]},
                  {"vy", vy[i]},
                  {"omega", omega[i]},
                  {"net force x", engine.force_x(i)},
                  {"net force y", engine.force_y(i)},
                  {"torque", engine.torque(i)}};
    for (const auto& f : fields) {
      if (!std::isfinite(f.value)) {
        return at_step(engine) + "disk " + std::to_string(i) + ": " + f.name + " = " +
               number(f.value) + " (not finite)";
      }
    }
  }
  const Disks& d = exported.disks;
  const Contacts& c = exported.contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const double h = contact_frame(exported, k).h;
    const int i = c.i[k], j = c.j[k];
    const double r = is_wall(j) ? d.radius[i] : std::min(d.radius[i], d.radius[j]);
    if (!(h <= limits.max_overlap_fraction * r)) {  // also catches h = nan
      return at_step(engine) + "contact of disk " + std::to_string(i) +
             (is_wall(j) ? " with wall " + std::to_string(-j) : " and disk " + std::to_string(j)) +
             ": overlap " + number(h) + " = " + number(h / r) +
             " of the smaller radius (limit sanity.max_overlap_fraction = " +
             number(limits.max_overlap_fraction) + ")";
    }
  }
  const double k_n = exported.material.k_n;
  for (std::size_t i = 0; i < n; ++i) {
    const double e =
        0.5 * (d.mass[i] * (vx[i] * vx[i] + vy[i] * vy[i]) + d.inertia[i] * omega[i] * omega[i]);
    const double scale = 0.5 * k_n * d.radius[i] * d.radius[i];
    if (!(e <= limits.max_kinetic_energy * scale)) {
      return at_step(engine) + "disk " + std::to_string(i) + ": kinetic energy " + number(e) +
             " = " + number(e / scale) + " K_N r^2 / 2 (limit sanity.max_kinetic_energy = " +
             number(limits.max_kinetic_energy) +
             "); the time step is probably too large (engine.dt_fraction)";
    }
  }
  return std::nullopt;
}

SanityMargins sanity_margins(const Configuration& state) {
  SanityMargins m;
  const Disks& d = state.disks;
  const Contacts& c = state.contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const int i = c.i[k], j = c.j[k];
    const double r = is_wall(j) ? d.radius[i] : std::min(d.radius[i], d.radius[j]);
    m.overlap_fraction = std::max(m.overlap_fraction, contact_frame(state, k).h / r);
  }
  for (std::size_t i = 0; i < d.size(); ++i) {
    const double e = 0.5 * (d.mass[i] * (d.vx[i] * d.vx[i] + d.vy[i] * d.vy[i]) +
                            d.inertia[i] * d.omega[i] * d.omega[i]);
    m.kinetic_energy =
        std::max(m.kinetic_energy, e / (0.5 * state.material.k_n * d.radius[i] * d.radius[i]));
  }
  return m;
}

}  // namespace granstab::dynamic
