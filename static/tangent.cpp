#include "static/tangent.hpp"

#include <algorithm>
#include <array>

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
      LocalRow t;  // t.dl per slot, once rather than per row (the same values)
      for (int b = 0; b < n_local; ++b) t[b] = f.tx * r.dx[b] + f.ty * r.dy[b];
      for (int a = 0; a < n_local; ++a) {
        const double g = gx * r.dx[a] + gy * r.dy[a];
        if (g == 0.0) continue;
        for (int b = 0; b < n_local; ++b) k[a][b] -= g * t[b] / f.d;
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

namespace {
bool has_load_stiffness(const Network& net) {
  return net.loading.measure == StressMeasure::cauchy && net.dofs.e[0] >= 0 && net.dofs.e[1] >= 0;
}
}  // namespace

void add_load_stiffness(const Network& net, std::vector<Eigen::Triplet<double>>& triplets) {
  const DofMap& m = net.dofs;
  if (!has_load_stiffness(net)) return;
  const double a0 = net.area();
  triplets.emplace_back(m.e[0], m.e[1], net.loading.sigma[0] * a0);
  triplets.emplace_back(m.e[1], m.e[0], net.loading.sigma[1] * a0);
}

namespace {

// The fixed pattern of a contact list (TangentParts::fixed_pattern): the compressed structure that
// setFromTriplets makes of every contact's whole block, and the position in it of each block
// entry, so that an assembly writes its values straight into a copy. A q1 run assembles many
// tangents on one contact list (the status iterations, the correctors, the checks); the triplet
// sort and the row- to column-major copy were ~2/3 of the assembly (perf, N = 1400).
struct FixedPattern {
  int n = -1;
  bool load = false;
  std::array<int, 2> cell{-1, -1};             // the key: the cell's dofs e1, e2,
  std::vector<std::array<int, n_local>> dofs;  // and each contact's dofs
  SparseMatrix zero;                           // the structure, all values 0
  std::vector<int> slot;                       // contact c, entry (a, b): value index, or -1
  std::vector<char> first;                     // the slot is its value's first term
  std::array<int, 2> load_slot{-1, -1};        // (e1, e2) and (e2, e1)
  std::array<char, 2> load_first{0, 0};

  bool matches(const Network& net, const std::vector<ContactState>& states, bool with_load) const {
    if (n != net.dofs.size || load != with_load || dofs.size() != states.size() ||
        cell[0] != net.dofs.e[0] || cell[1] != net.dofs.e[1])
      return false;
    for (std::size_t c = 0; c < states.size(); ++c)
      if (dofs[c] != states[c].rows.dof) return false;
    return true;
  }
};

int value_index(const SparseMatrix& k, int row, int col) {
  const int* begin = k.innerIndexPtr() + k.outerIndexPtr()[col];
  const int* end = k.innerIndexPtr() + k.outerIndexPtr()[col + 1];
  const int* at = std::lower_bound(begin, end, row);
  return at != end && *at == row ? static_cast<int>(at - k.innerIndexPtr()) : -1;
}

const FixedPattern& fixed_pattern_of(const Network& net, const std::vector<ContactState>& states,
                                     bool with_load) {
  thread_local FixedPattern p;
  if (p.matches(net, states, with_load)) return p;
  p.n = net.dofs.size;
  p.load = with_load;
  p.cell = {net.dofs.e[0], net.dofs.e[1]};
  p.dofs.resize(states.size());
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(states.size() * n_local * n_local + 2);
  for (std::size_t c = 0; c < states.size(); ++c) {
    p.dofs[c] = states[c].rows.dof;
    for (int a = 0; a < n_local; ++a)
      for (int b = 0; b < n_local; ++b)
        if (p.dofs[c][a] >= 0 && p.dofs[c][b] >= 0)
          triplets.emplace_back(p.dofs[c][a], p.dofs[c][b], 0.0);
  }
  const DofMap& m = net.dofs;
  if (with_load) {
    triplets.emplace_back(m.e[0], m.e[1], 0.0);
    triplets.emplace_back(m.e[1], m.e[0], 0.0);
  }
  p.zero = SparseMatrix(p.n, p.n);
  p.zero.setFromTriplets(triplets.begin(), triplets.end());
  p.zero.makeCompressed();
  p.slot.assign(states.size() * n_local * n_local, -1);
  for (std::size_t c = 0; c < states.size(); ++c)
    for (int a = 0; a < n_local; ++a)
      for (int b = 0; b < n_local; ++b)
        if (p.dofs[c][a] >= 0 && p.dofs[c][b] >= 0)
          p.slot[(c * n_local + a) * n_local + b] = value_index(p.zero, p.dofs[c][a], p.dofs[c][b]);
  p.load_slot = {-1, -1};
  if (with_load)
    p.load_slot = {value_index(p.zero, m.e[0], m.e[1]), value_index(p.zero, m.e[1], m.e[0])};
  // Every value has a term (the pattern is made of these entries); the first, in the assembly's
  // order, sets it and the others add to it.
  std::vector<char> seen(static_cast<std::size_t>(p.zero.nonZeros()), 0);
  const auto first_term = [&](int i) {
    const bool first = i >= 0 && !seen[i];
    if (first) seen[i] = 1;
    return static_cast<char>(first);
  };
  p.first.resize(p.slot.size());
  for (std::size_t e = 0; e < p.slot.size(); ++e) p.first[e] = first_term(p.slot[e]);
  p.load_first = {first_term(p.load_slot[0]), first_term(p.load_slot[1])};
  return p;
}

// Each assembly returns one named matrix, built in place (NRVO): with two in one function, the
// return would copy it (Eigen 3.4's SparseMatrix has no move constructor).

SparseMatrix on_fixed_pattern(const Network& net, const std::vector<ContactState>& states,
                              const std::vector<ContactStatus>& statuses,
                              const TangentParts& parts) {
  // Every listed contact writes its whole block. Each entry's terms are added in the order in
  // which setFromTriplets would sum them (contacts, then a, b), so the values are the same.
  const bool with_load = parts.load && has_load_stiffness(net);
  const FixedPattern& p = fixed_pattern_of(net, states, with_load);
  SparseMatrix k = with_structure_of(p.zero);
  double* value = k.valuePtr();
  const auto add = [value](int i, char first, double v) { value[i] = first ? v : value[i] + v; };
  for (std::size_t c = 0; c < states.size(); ++c) {
    const LocalMatrix kc = contact_stiffness(net, states[c], statuses[c], parts);
    const int* slot = &p.slot[c * n_local * n_local];
    const char* first = &p.first[c * n_local * n_local];
    for (int a = 0; a < n_local; ++a)
      for (int b = 0; b < n_local; ++b)
        if (slot[a * n_local + b] >= 0)
          add(slot[a * n_local + b], first[a * n_local + b], kc[a][b]);
  }
  if (with_load) {
    const double a0 = net.area();
    add(p.load_slot[0], p.load_first[0], net.loading.sigma[0] * a0);
    add(p.load_slot[1], p.load_first[1], net.loading.sigma[1] * a0);
  }
  return k;
}

SparseMatrix from_triplets(const Network& net, const std::vector<ContactState>& states,
                           const std::vector<ContactStatus>& statuses, const TangentParts& parts) {
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(states.size() * 40 + 2);
  for (std::size_t c = 0; c < states.size(); ++c) {
    if (statuses[c] == ContactStatus::open && states[c].f_n == 0.0) continue;
    const LocalMatrix kc = contact_stiffness(net, states[c], statuses[c], parts);
    const auto& dof = states[c].rows.dof;
    for (int a = 0; a < n_local; ++a) {
      if (dof[a] < 0) continue;
      for (int b = 0; b < n_local; ++b)
        if (dof[b] >= 0 && kc[a][b] != 0.0) triplets.emplace_back(dof[a], dof[b], kc[a][b]);
    }
  }
  if (parts.load) add_load_stiffness(net, triplets);
  SparseMatrix k(net.dofs.size, net.dofs.size);
  k.setFromTriplets(triplets.begin(), triplets.end());
  return k;
}

}  // namespace

SparseMatrix assemble_tangent(const Network& net, const std::vector<ContactState>& states,
                              const std::vector<ContactStatus>& statuses,
                              const TangentParts& parts) {
  return parts.fixed_pattern ? on_fixed_pattern(net, states, statuses, parts)
                             : from_triplets(net, states, statuses, parts);
}

SparseMatrix assemble_tangent(const Network& net, const std::vector<ContactState>& states,
                              const TangentParts& parts) {
  std::vector<ContactStatus> statuses(states.size());
  for (std::size_t c = 0; c < states.size(); ++c) statuses[c] = states[c].status;
  return assemble_tangent(net, states, statuses, parts);
}

}  // namespace granstab::statics
