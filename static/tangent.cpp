#include "static/tangent.hpp"

namespace granstab::statics {

LocalMatrix contact_stiffness(const Network& net, const ContactState& s, ContactStatus status,
                              const TangentParts& parts) {
  LocalMatrix k{};
  if (status == ContactStatus::open) return k;
  const ContactRows& r = s.rows;
  const double k_n = net.material.k_n, k_t = net.material.k_t;
  if (parts.material) {
    for (int a = 0; a < n_local; ++a)
      for (int b = 0; b < n_local; ++b) k[a][b] += k_n * r.bn[a] * r.bn[b];
    if (s.frictional) {
      if (status == ContactStatus::stick) {
        for (int a = 0; a < n_local; ++a)
          for (int b = 0; b < n_local; ++b) k[a][b] += k_t * r.bt[a] * r.bt0[b];
      } else {
        // F_T = s mu F_N: the tangential row follows the normal deflection (unsymmetric).
        const double sign = status == ContactStatus::slide_positive ? 1.0 : -1.0;
        const double c = sign * s.mu * k_n;
        for (int a = 0; a < n_local; ++a)
          for (int b = 0; b < n_local; ++b) k[a][b] += c * r.bt[a] * r.bn[b];
      }
    }
  }
  if (parts.geometric && (s.f_n != 0.0 || s.f_t != 0.0)) {
    const ContactFrame& f = s.frame;
    if (!s.wall) {
      // dn = t (t.dl)/d, dt = -n (t.dl)/d: the frozen forces turn with the branch vector.
      const double gx = s.f_n * f.tx - s.f_t * f.nx, gy = s.f_n * f.ty - s.f_t * f.ny;
      for (int a = 0; a < n_local; ++a) {
        const double g = gx * r.dx[a] + gy * r.dy[a];
        if (g == 0.0) continue;
        for (int b = 0; b < n_local; ++b) k[a][b] -= g * (f.tx * r.dx[b] + f.ty * r.dy[b]) / f.d;
      }
    }
    // Lever arms a = R - h/2 grow with the distance: da = B_N dq / 2 (the wall does not turn).
    for (int b = 0; b < n_local; ++b) {
      k[2][b] += 0.5 * s.f_t * r.bn[b];
      if (!s.wall) k[5][b] += 0.5 * s.f_t * r.bn[b];
    }
  }
  return k;
}

void add_load_stiffness(const Network& net, std::vector<Eigen::Triplet<double>>& triplets) {
  const DofMap& m = net.dofs;
  if (net.loading.measure != StressMeasure::cauchy || m.e[0] < 0 || m.e[1] < 0) return;
  const double a0 = net.area();
  triplets.emplace_back(m.e[0], m.e[1], net.loading.sigma[0] * a0);
  triplets.emplace_back(m.e[1], m.e[0], net.loading.sigma[1] * a0);
}

SparseMatrix assemble_tangent(const Network& net, const std::vector<ContactState>& states,
                              const std::vector<ContactStatus>& statuses,
                              const TangentParts& parts) {
  // all: every listed contact writes its whole block (TangentParts::fixed_pattern).
  const bool all = parts.fixed_pattern;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(states.size() * (all ? n_local * n_local : 40) + 2);
  for (std::size_t c = 0; c < states.size(); ++c) {
    if (!all && statuses[c] == ContactStatus::open && states[c].f_n == 0.0) continue;
    const LocalMatrix k = contact_stiffness(net, states[c], statuses[c], parts);
    const auto& dof = states[c].rows.dof;
    for (int a = 0; a < n_local; ++a) {
      if (dof[a] < 0) continue;
      for (int b = 0; b < n_local; ++b)
        if (dof[b] >= 0 && (all || k[a][b] != 0.0)) triplets.emplace_back(dof[a], dof[b], k[a][b]);
    }
  }
  if (parts.load) add_load_stiffness(net, triplets);
  SparseMatrix k(net.dofs.size, net.dofs.size);
  k.setFromTriplets(triplets.begin(), triplets.end());
  return k;
}

SparseMatrix assemble_tangent(const Network& net, const std::vector<ContactState>& states,
                              const TangentParts& parts) {
  std::vector<ContactStatus> statuses(states.size());
  for (std::size_t c = 0; c < states.size(); ++c) statuses[c] = states[c].status;
  return assemble_tangent(net, states, statuses, parts);
}

}  // namespace granstab::statics
