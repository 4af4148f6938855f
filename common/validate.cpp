#include <stdexcept>
#include <string>

#include "cell.hpp"
#include "material.hpp"

namespace granstab {
namespace {
void require(bool ok, const std::string& field, const std::string& what) {
  if (!ok) throw std::invalid_argument(field + ": " + what);
}
}  // namespace

void validate(const Material& m) {
  require(std::isfinite(m.k_n) && m.k_n > 0.0, "material.k_n", "must be finite and > 0");
  require(std::isfinite(m.k_t) && m.k_t > 0.0, "material.k_t", "must be finite and > 0");
  require(std::isfinite(m.mu) && m.mu >= 0.0, "material.mu", "must be finite and >= 0");
  require(std::isfinite(m.zeta) && m.zeta >= 0.0 && m.zeta <= 1.0, "material.zeta",
          "must lie in [0, 1]");
  require(std::isfinite(m.mu_wall) && m.mu_wall >= 0.0, "material.mu_wall",
          "must be finite and >= 0");
}

void validate(const Cell& c) {
  for (int a = 0; a < 2; ++a) {
    const std::string ax = std::to_string(a + 1);
    require(std::isfinite(c.length[a]) && c.length[a] > 0.0, "cell.L" + ax,
            "must be finite and > 0");
    require(std::isfinite(c.length_rate[a]), "cell.L" + ax + "_rate", "must be finite");
    require(std::isfinite(c.mass[a]) && c.mass[a] > 0.0, "cell.mass" + ax,
            "must be finite and > 0");
  }
}

}  // namespace granstab
