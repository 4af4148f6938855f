#include "static/kinematics.hpp"

#include <cmath>

namespace granstab::statics {
namespace {

double dof_value(const Eigen::VectorXd& dq, int index) { return index >= 0 ? dq[index] : 0.0; }

// Start-of-step vector from r_i0 to the partner's material point, the column of D at (e1, e2):
// the image of j for a disk, for a wall the point of the wall facing the disk, which moves with
// the wall along n and not along the wall.
std::array<double, 2> reference_branch(const Network& net, std::size_t c) {
  const Contacts& k = net.contacts;
  const int i = k.i[c], j = k.j[c];
  const double xi = net.x[i], yi = net.y[i];
  if (!is_wall(j))
    return {net.x[j] + k.k1[c] * net.length[0] - xi, net.y[j] + k.k2[c] * net.length[1] - yi};
  switch (static_cast<Wall>(j)) {
    case wall_right:
      return {net.length[0] - xi, -yi};
    case wall_top:
      return {-xi, net.length[1] - yi};
    default:
      return {-xi, -yi};  // the walls through the origin never move
  }
}

ContactFrame frame_at(const Network& net, std::size_t c, const std::array<double, 2>& e,
                      const std::array<double, 2>& w, double uxi, double uyi, double uxj,
                      double uyj) {
  const int i = net.contacts.i[c], j = net.contacts.j[c];
  if (!is_wall(j)) {
    const double lx = (1.0 + e[0]) * w[0] + uxj - uxi;
    const double ly = (1.0 + e[1]) * w[1] + uyj - uyi;
    return disk_disk_frame(lx, ly, net.radius[i], net.radius[j]);
  }
  Cell cell;
  cell.boundary = Boundary::walls;
  cell.length = {net.length[0] * (1.0 + e[0]), net.length[1] * (1.0 + e[1])};
  const double x = (1.0 + e[0]) * net.x[i] + uxi;
  const double y = (1.0 + e[1]) * net.y[i] + uyi;
  return disk_wall_frame(x, y, net.radius[i], static_cast<Wall>(j), cell);
}

}  // namespace

std::array<double, 2> cell_extension(const Network& net, const Eigen::VectorXd& dq) {
  std::array<double, 2> e{};
  for (int a = 0; a < 2; ++a)
    e[a] = net.dofs.e[a] >= 0 ? dq[net.dofs.e[a]] : net.loading.e_imposed[a];
  return e;
}

ContactState evaluate_contact(const Network& net, std::size_t c, const Eigen::VectorXd& dq,
                              std::optional<ContactStatus> forced) {
  const Contacts& k = net.contacts;
  const DofMap& m = net.dofs;
  const int i = k.i[c], j = k.j[c];
  ContactState s;
  s.wall = is_wall(j);
  const double mu = net.friction(c);
  s.mu = mu;
  s.frictional = mu > 0.0;

  ContactRows& r = s.rows;
  r.dof = {m.ux[i], m.uy[i], m.theta[i], -1, -1, -1, m.e[0], m.e[1]};
  if (!s.wall) {
    r.dof[3] = m.ux[j];
    r.dof[4] = m.uy[j];
    r.dof[5] = m.theta[j];
  }
  const std::array<double, 2> w = reference_branch(net, c);
  const double partner = s.wall ? 0.0 : 1.0;
  r.dx = {-1.0, 0.0, 0.0, partner, 0.0, 0.0, w[0], 0.0};
  r.dy = {0.0, -1.0, 0.0, 0.0, partner, 0.0, 0.0, w[1]};

  const std::array<double, 2> e = cell_extension(net, dq);
  const double uxi = dof_value(dq, r.dof[0]), uyi = dof_value(dq, r.dof[1]);
  const double uxj = dof_value(dq, r.dof[3]), uyj = dof_value(dq, r.dof[4]);
  s.frame = frame_at(net, c, e, w, uxi, uyi, uxj, uyj);
  s.frame0 = frame_at(net, c, {0.0, 0.0}, w, 0.0, 0.0, 0.0, 0.0);

  const ContactFrame& f = s.frame;
  const ContactFrame& f0 = s.frame0;
  for (int a = 0; a < n_local; ++a) {
    r.bn[a] = f.nx * r.dx[a] + f.ny * r.dy[a];
    r.bt[a] = f.tx * r.dx[a] + f.ty * r.dy[a];
    r.bt0[a] = f0.tx * r.dx[a] + f0.ty * r.dy[a];
  }
  r.bt[2] -= f.a_i;
  r.bt0[2] -= f0.a_i;
  if (!s.wall) {
    r.bt[5] -= f.a_j;
    r.bt0[5] -= f0.a_j;
  }

  // Tangential increment over the step, d delta_T = B_T(q0) dq (STATIC.md §S1): exactly linear.
  const double dlx = r.dx[6] * e[0] + (uxj - uxi);
  const double dly = r.dy[7] * e[1] + (uyj - uyi);
  const double dth_i = dof_value(dq, r.dof[2]);
  const double dth_j = dof_value(dq, r.dof[5]);
  const double d_delta = tangential_rate(f0, dlx, dly, dth_i, dth_j);
  const double delta_trial = k.delta_t[c] + d_delta;

  // A rattler (removed by the preparation: DofMap::rattler) has no force balance, so its contacts
  // carry no force (SPEC §2): otherwise an overlapping listed contact makes it an obstacle moved
  // affinely with the cell that pushes its neighbour with an unbalanced force. They stay listed
  // while they overlap (advance), so that the rattler rejoins at the next preparation once two of
  // them carry load. (docs/static.md, "Round-off-robust decisions": whether a grazing contact of
  // a new rattler stayed listed was round-off and chose between two states of periodic-n100.)
  const bool closed = f.h > 0.0 && !m.is_rattler(i) && (s.wall || !m.is_rattler(j));
  s.f_n = closed ? net.material.k_n * f.h : 0.0;
  if (!closed) {
    s.status = ContactStatus::open;
    s.f_t = 0.0;
    s.delta_t = 0.0;
    return s;
  }
  if (forced && *forced != ContactStatus::open) {
    s.status = *forced;
    if (*forced == ContactStatus::stick || !s.frictional) {
      s.f_t = s.frictional ? -net.material.k_t * delta_trial : 0.0;
    } else {
      s.f_t = (*forced == ContactStatus::slide_positive ? 1.0 : -1.0) * mu * s.f_n;
    }
    s.delta_t = -s.f_t / net.material.k_t;
    return s;
  }
  const TangentialForce t = tangential_force(net.material.k_t, mu, s.f_n, delta_trial);
  s.f_t = t.f_t;
  s.delta_t = t.delta_t;
  if (!t.sliding || !s.frictional)
    s.status = s.frictional ? ContactStatus::stick : ContactStatus::slide_positive;
  else
    s.status = t.f_t > 0.0 ? ContactStatus::slide_positive : ContactStatus::slide_negative;
  return s;
}

bool same_contacts(const Network& net, const Network& moved) {
  return net.loading.e_imposed == moved.loading.e_imposed;  // cell_extension's only load
}

std::vector<ContactState> evaluate_contacts(const Network& net, const Eigen::VectorXd& dq,
                                            const std::vector<ContactStatus>* forced) {
  // Reserved, not sized: a ContactState is ~0.5 kB, and value-initialising the vector before
  // overwriting it doubled the memory written (perf: evaluate_contacts' own time).
  std::vector<ContactState> states;
  states.reserve(net.contacts.size());
  for (std::size_t c = 0; c < net.contacts.size(); ++c) {
    std::optional<ContactStatus> f;
    if (forced) f = (*forced)[c];
    states.push_back(evaluate_contact(net, c, dq, f));
  }
  return states;
}

Eigen::VectorXd contact_forces(const Network& net, const std::vector<ContactState>& states) {
  Eigen::VectorXd g = Eigen::VectorXd::Zero(net.dofs.size);
  for (const ContactState& s : states) {
    if (s.f_n == 0.0 && s.f_t == 0.0) continue;
    for (int a = 0; a < n_local; ++a)
      if (s.rows.dof[a] >= 0) g[s.rows.dof[a]] += s.rows.bn[a] * s.f_n + s.rows.bt[a] * s.f_t;
  }
  return g;
}

Eigen::VectorXd external_forces(const Network& net, const Eigen::VectorXd& dq) {
  const DofMap& m = net.dofs;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(m.size);
  const std::array<double, 2> e = cell_extension(net, dq);
  const Loading& load = net.loading;
  // Work of the prescribed stress on the deforming rectangle: side a moves by L_a0 de_a and
  // carries sigma_a times the current (Cauchy) or reference (nominal) length of the other side.
  for (int a = 0; a < 2; ++a) {
    if (m.e[a] < 0) continue;
    const int b = 1 - a;
    const double other = load.measure == StressMeasure::cauchy ? net.length[b] * (1.0 + e[b])
                                                               : load.nominal_length[b];
    f[m.e[a]] -= load.sigma[a] * net.length[a] * other;
  }
  if (!load.dead.empty()) {
    for (std::size_t i = 0; i < net.n_disks(); ++i) {
      if (m.ux[i] >= 0) f[m.ux[i]] += load.dead[3 * i];
      if (m.uy[i] >= 0) f[m.uy[i]] += load.dead[3 * i + 1];
      if (m.theta[i] >= 0) f[m.theta[i]] += load.dead[3 * i + 2];
    }
  }
  return f;
}

Eigen::VectorXd residual(const Network& net, const Eigen::VectorXd& dq,
                         const std::vector<ContactState>& states) {
  return contact_forces(net, states) + external_forces(net, dq);
}

std::array<double, 2> contact_stress(const Network& net, const Eigen::VectorXd& dq,
                                     const std::vector<ContactState>& states) {
  const std::array<double, 2> e = cell_extension(net, dq);
  // sum_c f_a w_a with w the current vector from r_i to the partner's material point: the branch
  // vector for disks; for walls, with the force balance of every disk, the sum becomes the force
  // on the mobile walls times the box length, as SPEC §2 requires of both measures.
  std::array<double, 2> s{0.0, 0.0};
  for (const ContactState& c : states) {
    if (c.f_n == 0.0 && c.f_t == 0.0) continue;
    const ContactRows& r = c.rows;
    const double du_x = dof_value(dq, r.dof[3]) - dof_value(dq, r.dof[0]);
    const double du_y = dof_value(dq, r.dof[4]) - dof_value(dq, r.dof[1]);
    const double wx = (1.0 + e[0]) * r.dx[6] + du_x;
    const double wy = (1.0 + e[1]) * r.dy[7] + du_y;
    s[0] += (c.f_n * c.frame.nx + c.f_t * c.frame.tx) * wx;
    s[1] += (c.f_n * c.frame.ny + c.f_t * c.frame.ty) * wy;
  }
  const double area = net.area() * (1.0 + e[0]) * (1.0 + e[1]);
  return {s[0] / area, s[1] / area};
}

}  // namespace granstab::statics
