#pragma once
// Contact parameters, identical in every contact (SPEC §1.1), in the units of SPEC §1
// (a = 1, m = 1, P = 1): stiffnesses are forces per unit length in units of P, so K_N = kappa.
#include <cmath>
#include <limits>

namespace granstab {

struct Material {
  double k_n = 1e4;      // normal stiffness K_N
  double k_t = 1e4;      // tangential stiffness K_T
  double mu = 0.5;       // inter-disk Coulomb friction coefficient
  double zeta = 1.0;     // normal damping, fraction of the critical damping of each pair
  double mu_wall = 0.0;  // disk-wall friction; SPEC §1.3 walls are frictionless by default

  // Dimensionless construction (SPEC §1.2): kappa = K_N / P.
  static Material from_kappa(double kappa, double kt_over_kn, double mu, double zeta,
                             double pressure = 1.0) {
    Material m;
    m.k_n = kappa * pressure;
    m.k_t = kt_over_kn * m.k_n;
    m.mu = mu;
    m.zeta = zeta;
    return m;
  }

  double kappa(double pressure = 1.0) const { return k_n / pressure; }
  double kt_over_kn() const { return k_t / k_n; }

  // alpha_ij = zeta * 2 sqrt(K_N m_i m_j / (m_i + m_j)); a wall is an infinitely heavy partner,
  // whose reduced mass is m_i (pass m_j = +inf).
  double damping_coefficient(double m_i, double m_j) const {
    const double reduced = std::isinf(m_j) ? m_i : m_i * m_j / (m_i + m_j);
    return zeta * 2.0 * std::sqrt(k_n * reduced);
  }
};

// Throws std::invalid_argument naming the offending field (material.k_n, ...).
void validate(const Material& material);

}  // namespace granstab
