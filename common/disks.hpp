#pragma once
// The disks of SPEC §1 as a structure of arrays: the hot loops stream through one field at a
// time, and the file format and both solvers index the same arrays.
#include <cstddef>
#include <vector>

namespace granstab {

// SPEC §1 with a = 1, m = 1: m_i = (d_i / a)^2, I_i = m_i d_i^2 / 8 (homogeneous disk).
inline double disk_mass(double radius) { return 4.0 * radius * radius; }
inline double disk_inertia(double mass, double radius) { return 0.5 * mass * radius * radius; }

struct Disks {
  // Positions. Periodic cells: wrapped into [0, L1) x [0, L2). Walls: inside [0, L1] x [0, L2].
  std::vector<double> x, y;
  std::vector<double> radius, mass, inertia;
  // Velocities are the fluctuating (non-affine) part: in a periodic cell whose lengths change
  // at rates dL_a/dt, the velocity of disk i is (dL_a/dt / L_a) r_ia + v_ia.
  std::vector<double> vx, vy;
  std::vector<double> omega;  // spin, counter-clockwise positive
  std::vector<double> theta;  // accumulated rotation angle

  std::size_t size() const { return x.size(); }
  bool empty() const { return x.empty(); }

  void resize(std::size_t n) {
    for (auto* v : fields()) v->resize(n, 0.0);
  }
  void reserve(std::size_t n) {
    for (auto* v : fields()) v->reserve(n);
  }
  // Adds a disk at rest with the mass and inertia of SPEC §1.
  std::size_t add(double x0, double y0, double r) {
    const double m = disk_mass(r);
    x.push_back(x0);
    y.push_back(y0);
    radius.push_back(r);
    mass.push_back(m);
    inertia.push_back(disk_inertia(m, r));
    vx.push_back(0.0);
    vy.push_back(0.0);
    omega.push_back(0.0);
    theta.push_back(0.0);
    return size() - 1;
  }

  std::vector<std::vector<double>*> fields() {
    return {&x, &y, &radius, &mass, &inertia, &vx, &vy, &omega, &theta};
  }
};

}  // namespace granstab
