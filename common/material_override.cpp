#include "material_override.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>

#include "io/json_text.hpp"
#include "measurements.hpp"

namespace granstab {
namespace {

double* material_field(Material& m, const std::string& key) {
  if (key == "material.k_n") return &m.k_n;
  if (key == "material.k_t") return &m.k_t;
  if (key == "material.mu") return &m.mu;
  if (key == "material.zeta") return &m.zeta;
  if (key == "material.mu_wall") return &m.mu_wall;
  return nullptr;
}

}  // namespace

std::pair<std::string, double> parse_material_setting(const std::string& text) {
  const std::size_t eq = text.find('=');
  const std::string key = text.substr(0, eq);
  Material probe;
  if (eq == std::string::npos || !material_field(probe, key))
    throw std::invalid_argument("--set " + text +
                                ": expected material.KEY=VALUE with KEY one of k_n, k_t, mu, "
                                "zeta, mu_wall");
  const std::string value = text.substr(eq + 1);
  double v = 0.0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), v);
  if (value.empty() || error != std::errc() || end != value.data() + value.size())
    throw std::invalid_argument("--set " + text + ": '" + value + "' is not a number");
  return {key, v};
}

MaterialOverrideReport apply_material_overrides(Configuration& config,
                                                const MaterialOverrides& overrides) {
  MaterialOverrideReport report;
  if (overrides.empty()) return report;
  Material m = config.material;
  for (const auto& [key, value] : overrides.set) {
    double* field = material_field(m, key);
    if (!field) throw std::invalid_argument("--set " + key + ": unknown material key");
    *field = value;
  }
  if (overrides.kt_ratio) {
    if (!(std::isfinite(*overrides.kt_ratio) && *overrides.kt_ratio > 0.0))
      throw std::invalid_argument("--kt-ratio: must be a finite number > 0");
    m.k_t = *overrides.kt_ratio * m.k_n;
  }
  if (overrides.mu) m.mu = *overrides.mu;
  validate(m);

  Contacts& c = config.contacts;
  if (m.k_t != config.material.k_t) {
    const double scale = config.material.k_t / m.k_t;
    for (double& dt : c.delta_t) dt *= scale;
  }
  config.material = m;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const double h = contact_frame(config, k).h;
    const double f_n = m.k_n * h;
    const double mu = is_wall(c.j[k]) ? m.mu_wall : m.mu;
    const double f_t = -m.k_t * c.delta_t[k];
    // Round-off allowance: a sliding contact sits on the cone to a few ulps.
    if (!(f_n > 0.0) || std::abs(f_t) <= mu * f_n * (1.0 + 1e-12)) continue;
    if (!overrides.clip_to_cone) {
      const int i = c.i[k], j = c.j[k];
      throw std::invalid_argument(
          "contact " + std::to_string(k) + " (disk " + std::to_string(i) +
          (is_wall(j) ? " with wall " + std::to_string(-j) : " and disk " + std::to_string(j)) +
          ") carries |F_T| / F_N = " + json_number(std::abs(f_t) / f_n) +
          " > mu = " + json_number(mu) +
          " (the new friction); --clip-to-cone moves such contacts onto the cone");
    }
    c.delta_t[k] = -std::copysign(mu * f_n, f_t) / m.k_t;
    c.status[k] = f_t > 0.0 ? ContactStatus::slide_positive : ContactStatus::slide_negative;
    ++report.clipped;
  }
  return report;
}

std::string material_json(const Material& m) {
  return "{\"k_n\": " + json_number(m.k_n) + ", \"k_t\": " + json_number(m.k_t) +
         ", \"kt_ratio\": " + json_number(m.kt_over_kn()) + ", \"mu\": " + json_number(m.mu) +
         ", \"zeta\": " + json_number(m.zeta) + ", \"mu_wall\": " + json_number(m.mu_wall) + "}";
}

}  // namespace granstab
