#include "settings.hpp"

#include <limits>
#include <stdexcept>
#include <string>

namespace granstab::protocols {

Material read_material(RunConfig& rc, const Material& fallback) {
  Material m = fallback;
  const double kappa = rc.number("material.kappa", fallback.kappa(), 1.0, 1e9);
  const double kt_over_kn = rc.number("material.kt_over_kn", fallback.kt_over_kn(), 0.0, 10.0);
  m.k_n = kappa;
  m.k_t = kt_over_kn * kappa;
  m.mu = rc.number("material.mu", fallback.mu, 0.0, 100.0);
  m.zeta = rc.number("material.zeta", fallback.zeta, 0.0, 1.0);
  m.mu_wall = rc.number("material.mu_wall", fallback.mu_wall, 0.0, 100.0);
  return m;
}

EquilibrationOptions read_equilibration(RunConfig& rc) {
  EquilibrationOptions o;
  o.tolerances.force = rc.number("equilibrium.force", o.tolerances.force, 1e-15, 1.0);
  o.tolerances.torque = rc.number("equilibrium.torque", o.tolerances.torque, 1e-15, 1.0);
  o.tolerances.stress = rc.number("equilibrium.stress", o.tolerances.stress, 1e-15, 1.0);
  o.check_interval = static_cast<std::uint64_t>(rc.integer(
      "equilibrium.check_interval", static_cast<std::int64_t>(o.check_interval), 1, 100'000'000));
  o.max_steps = static_cast<std::uint64_t>(rc.integer("equilibrium.max_steps",
                                                      static_cast<std::int64_t>(o.max_steps), 0,
                                                      std::numeric_limits<std::int64_t>::max()));
  return o;
}

EngineOptions read_engine_options(RunConfig& rc) {
  EngineOptions o;
  // Up to 10, far beyond the stability limit of velocity Verlet (omega dt < 2 for the stiffest
  // contact mode, omega ~ 2 sqrt(K_N / m_min) in a packing, so dt_fraction < ~1),
  // so that a run with too large a step is stopped by the sanity guards with a clear message
  // (docs/reliability.md) rather than refused as a setting.
  o.dt_fraction = rc.number("engine.dt_fraction", o.dt_fraction, 1e-4, 10.0);
  o.skin = rc.number("engine.skin", o.skin, 1e-3, 10.0);
  return o;
}

std::filesystem::path required_path(RunConfig& rc, std::string_view key) {
  const auto p = rc.path(key);
  if (!p) {
    throw std::invalid_argument(rc.source_name() + ": " + std::string(key) + ": required");
  }
  return *p;
}

std::filesystem::path existing_file(RunConfig& rc, std::string_view key) {
  const auto p = required_path(rc, key);
  if (!std::filesystem::is_regular_file(p)) {
    throw std::invalid_argument(rc.source_name() + ": " + std::string(key) + " = \"" + p.string() +
                                "\": no such file");
  }
  return p;
}

}  // namespace granstab::protocols
