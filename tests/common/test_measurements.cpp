// SPEC §2 measurements on configurations whose answers are known by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/measurements.hpp"
#include "tiny_samples.hpp"

namespace granstab {
namespace {

constexpr double sqrt3 = std::numbers::sqrt3;

TEST(Measurements, TriangularLatticeUnderUnitPressure) {
  const double kappa = 1e3;
  const Configuration c = samples::triangular_lattice(kappa);
  const Measurements m = measure(c);
  // Hand computation (tiny_samples.cpp): sigma = sqrt(3) F_N / s with F_N = K_N h, s = 1 - h.
  const double h = samples::triangular_lattice_overlap(kappa);
  const double s = 1.0 - h;
  const double sigma_hand = sqrt3 * kappa * h / s;
  EXPECT_NEAR(sigma_hand, 1.0, 1e-14);
  EXPECT_NEAR(m.sigma[0][0], sigma_hand, 1e-12);
  EXPECT_NEAR(m.sigma[1][1], sigma_hand, 1e-12);
  EXPECT_NEAR(m.sigma[0][1], 0.0, 1e-12);
  EXPECT_NEAR(m.sigma[1][0], 0.0, 1e-12);
  EXPECT_NEAR(m.q, 0.0, 1e-12);
  // Phi of a triangular lattice: pi / (2 sqrt 3) at contact, divided by s^2 with overlaps.
  EXPECT_NEAR(m.phi, std::numbers::pi / (2.0 * sqrt3) / (s * s), 1e-14);
  EXPECT_EQ(m.n_disks, 16u);
  EXPECT_EQ(m.n_contacts_carrying, 48u);
  EXPECT_EQ(m.n_rattlers, 0u);
  EXPECT_DOUBLE_EQ(m.z, 6.0);
  EXPECT_DOUBLE_EQ(m.x0, 0.0);
  EXPECT_DOUBLE_EQ(m.x_s, 0.0);
  EXPECT_LT(m.f_2, 1e-12);
  EXPECT_LT(m.max_net_force, 1e-12);
  EXPECT_DOUBLE_EQ(m.e_c, 0.0);
  EXPECT_DOUBLE_EQ(m.epsilon_1, 0.0);
  EXPECT_DOUBLE_EQ(m.epsilon_v, 0.0);
}

TEST(Measurements, SquareStackStressEqualsWallForcesPerLength) {
  const int n = 3;
  const double kappa = 1e3;
  const Configuration c = samples::square_stack(n, kappa);
  const Measurements m = measure(c);
  // Force on the right wall: one chain per row, each carrying F = K_N h; over the wall length.
  const double wall_force = n * kappa * samples::square_stack_overlap(n, kappa);
  EXPECT_NEAR(m.sigma[0][0], wall_force / c.cell.length[1], 1e-12);
  EXPECT_NEAR(m.sigma[1][1], wall_force / c.cell.length[0], 1e-12);
  EXPECT_NEAR(m.sigma[0][0], 1.0, 1e-12);
  EXPECT_NEAR(m.sigma[1][1], 1.0, 1e-12);
  // The second measure of SPEC §2: wall forces over wall lengths agree with the contact sum.
  const auto walls = wall_forces(c, contact_loads(c));
  EXPECT_NEAR(walls[0], wall_force, 1e-12);                        // left
  EXPECT_NEAR(walls[1], wall_force, 1e-12);                        // right
  EXPECT_NEAR(walls[3] / c.cell.length[0], m.sigma[1][1], 1e-12);  // top
  EXPECT_NEAR(walls[2] / c.cell.length[0], m.sigma[1][1], 1e-12);  // bottom
  // Corner disks touch two walls and two disks: every disk has 4 contacts.
  EXPECT_EQ(m.n_network_disk_disk, 12u);
  EXPECT_EQ(m.n_network_wall, 12u);
  EXPECT_DOUBLE_EQ(m.z, (2.0 * 12 + 12) / 9);
  EXPECT_LT(m.max_net_force, 1e-12);
}

// Two disks in contact: radii 0.5 and 0.45, branch (0.54, 0.72), d = 0.9, h = 0.05, with a
// tangential elastic displacement. Placed in the cell interior, across x = L1, and across the
// corner.
struct PairCase {
  double xi, yi;
  int k1, k2;
};

Configuration pair_configuration(const PairCase& p) {
  Configuration c;
  c.cell.length = {5.0, 4.0};
  c.material = Material::from_kappa(1e3, 0.5, 0.5, 1.0);
  double xj = p.xi + 0.54 - p.k1 * c.cell.length[0];
  double yj = p.yi + 0.72 - p.k2 * c.cell.length[1];
  c.disks.add(p.xi, p.yi, 0.5);
  c.disks.add(xj, yj, 0.45);
  c.contacts.add(0, 1, p.k1, p.k2, 2e-3);
  return c;
}

TEST(Measurements, PairStressIsTheSameAcrossPeriodicBoundaries) {
  const double area = 20.0, d = 0.9, nx = 0.6, ny = 0.8, tx = -0.8, ty = 0.6;
  const double f_n = 1e3 * 0.05, f_t = -0.5e3 * 2e-3;
  const double hand[2][2] = {
      {(f_n * nx + f_t * tx) * d * nx / area, (f_n * nx + f_t * tx) * d * ny / area},
      {(f_n * ny + f_t * ty) * d * nx / area, (f_n * ny + f_t * ty) * d * ny / area}};
  for (const PairCase& p : {PairCase{2.0, 2.0, 0, 0}, PairCase{4.8, 2.0, 1, 0},
                            PairCase{4.8, 3.7, 1, 1}, PairCase{2.0, 3.5, 0, 1}}) {
    const Configuration c = pair_configuration(p);
    ASSERT_GE(c.disks.x[1], 0.0);
    ASSERT_GE(c.disks.y[1], 0.0);
    const StressTensor s = stress_tensor(c, contact_loads(c));
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        EXPECT_NEAR(s[a][b], hand[a][b], 1e-12)
            << "pair at " << p.xi << ", " << p.yi << " sigma" << a + 1 << b + 1;
    // Listing the contact as (j, i) with the opposite image flips both f and l.
    Configuration swapped = c;
    swapped.contacts.clear();
    swapped.contacts.add(1, 0, -p.k1, -p.k2, 2e-3);
    const StressTensor t = stress_tensor(swapped, contact_loads(swapped));
    EXPECT_NEAR(t[0][0], hand[0][0], 1e-12);
    EXPECT_NEAR(t[1][1], hand[1][1], 1e-12);
  }
}

TEST(Measurements, PairForcesTorquesAndTheRattlerRule) {
  const Configuration c = pair_configuration({4.8, 3.7, 1, 1});
  const auto loads = contact_loads(c);
  const NetForces net = net_forces(c, loads);
  const double f_n = 50.0, f_t = -1.0;
  const double fx = f_n * 0.6 + f_t * -0.8, fy = f_n * 0.8 + f_t * 0.6;
  EXPECT_NEAR(net.fx[1], fx, 1e-11);
  EXPECT_NEAR(net.fy[1], fy, 1e-11);
  EXPECT_NEAR(net.fx[0], -fx, 1e-11);
  EXPECT_NEAR(net.fy[0], -fy, 1e-11);
  // Lever arms R - h/2; a negative F_T turns both disks counter-clockwise.
  EXPECT_NEAR(net.torque[0], -(0.5 - 0.025) * f_t, 1e-11);
  EXPECT_NEAR(net.torque[1], -(0.45 - 0.025) * f_t, 1e-11);
  // One contact each: both are rattlers, so the force network is empty.
  const Measurements m = measure(c);
  EXPECT_EQ(m.n_rattlers, 2u);
  EXPECT_DOUBLE_EQ(m.x0, 1.0);
  EXPECT_DOUBLE_EQ(m.z, 0.0);
  EXPECT_DOUBLE_EQ(m.f_2, 0.0);
}

// Three disks of radius 1/2 at the corners of an equilateral triangle of side 0.98, in a large
// periodic cell, and optionally a chain of three disks hanging from disk 0 along -x.
Configuration triangle(bool with_chain) {
  Configuration c;
  c.cell.length = {20.0, 20.0};
  c.material = Material::from_kappa(1e3, 1.0, 0.5, 1.0);
  c.disks.add(10.0, 10.0, 0.5);
  c.disks.add(10.98, 10.0, 0.5);
  c.disks.add(10.49, 10.0 + 0.98 * sqrt3 / 2, 0.5);
  if (with_chain)
    for (int k = 1; k <= 3; ++k) c.disks.add(10.0 - 0.98 * k, 10.0, 0.5);
  samples::add_contacts_by_geometry(c);
  return c;
}

TEST(Measurements, TriangleNetForcesAndZ) {
  const Configuration c = triangle(false);
  const Measurements m = measure(c);
  ASSERT_EQ(m.n_contacts_carrying, 3u);
  // Each disk is pushed by two contacts 60 degrees apart: |F| = 2 F_N cos 30 = sqrt(3) F_N.
  const double f_n = 1e3 * 0.02;
  EXPECT_NEAR(m.max_net_force, sqrt3 * f_n, 1e-9);
  EXPECT_NEAR(m.f_2, sqrt3 * f_n, 1e-9);
  EXPECT_EQ(m.n_rattlers, 0u);
  EXPECT_DOUBLE_EQ(m.z, 2.0);
}

TEST(Measurements, DiskWithOneContactIsARattlerAndChainsCollapseIteratively) {
  Configuration c = triangle(true);
  ASSERT_EQ(c.contacts.size(), 6u);  // triangle 0-1-2, chain 0-3, 3-4, 4-5
  // Disks 3 and 4 have two contacts each: only iterating the removal from 5 inwards finds them.
  const auto rattler = find_rattlers(c, contact_loads(c));
  EXPECT_EQ(rattler, (std::vector<std::uint8_t>{0, 0, 0, 1, 1, 1}));
  const Measurements m = measure(c);
  EXPECT_DOUBLE_EQ(m.x0, 0.5);
  EXPECT_EQ(m.n_network_disk_disk, 3u);
  EXPECT_DOUBLE_EQ(m.z, 2.0);  // 2 * 3 contacts / 3 disks
  // A shorter chain collapses too (a single pass of the rule would keep disk 3).
  for (auto* f : c.disks.fields()) f->resize(5);
  c.contacts = {};
  samples::add_contacts_by_geometry(c);
  ASSERT_EQ(c.contacts.size(), 5u);
  EXPECT_EQ(find_rattlers(c, contact_loads(c)), (std::vector<std::uint8_t>{0, 0, 0, 1, 1}));
}

TEST(Measurements, ListedContactsWithoutOverlapCarryNoForce) {
  Configuration c = triangle(false);
  // Open the 1-2 contact (d = 1.006) but keep 0-2 (d = 0.956): move disk 2 by -0.05 along x.
  // The open contact stays in the list.
  c.disks.x[2] -= 0.05;
  const auto loads = contact_loads(c);
  int carrying = 0;
  for (const auto& l : loads) carrying += l.carrying;
  ASSERT_EQ(carrying, 2);
  const auto rattler = find_rattlers(c, loads);
  EXPECT_EQ(rattler, (std::vector<std::uint8_t>{1, 1, 1}));  // 2 has one contact, then 1, then 0
  EXPECT_EQ(measure(c).n_contacts_listed, 3u);
}

TEST(Measurements, WallContactsCountForTheirDisk) {
  Configuration c;
  c.cell.boundary = Boundary::walls;
  c.cell.length = {3.0, 3.0};
  c.material = Material::from_kappa(1e3, 0.5, 0.25, 1.0);
  c.disks.add(0.49, 0.49, 0.5);         // touches the left and bottom walls
  c.disks.add(0.49 + 0.98, 0.49, 0.5);  // touches disk 0 only (the bottom wall: no, 0.49 < 0.5!)
  c.disks.y[1] = 0.52;                  // lift it off the bottom wall
  c.disks.x[1] = 0.49 + std::sqrt(0.98 * 0.98 - 0.03 * 0.03);
  samples::add_contacts_by_geometry(c);
  ASSERT_EQ(c.contacts.size(), 3u);
  const Measurements m = measure(c);
  EXPECT_EQ(m.n_rattlers, 1u);  // disk 1
  EXPECT_EQ(m.n_network_wall, 2u);
  EXPECT_EQ(m.n_network_disk_disk, 0u);
  EXPECT_DOUBLE_EQ(m.z, 2.0);  // a wall contact counts once, for its disk
}

TEST(Measurements, SlidingFractionUsesTheCoulombCone) {
  Configuration c = triangle(false);
  const auto loads = contact_loads(c);
  const double mu = c.material.mu, k_t = c.material.k_t;
  c.contacts.delta_t[0] = -mu * loads[0].f_n / k_t;        // exactly on the cone
  c.contacts.delta_t[1] = 10.0 * mu * loads[1].f_n / k_t;  // beyond it: returned to the cone
  c.contacts.delta_t[2] = 0.5 * mu * loads[2].f_n / k_t;   // inside: sticking
  const Measurements m = measure(c);
  EXPECT_EQ(m.n_sliding, 2u);
  EXPECT_DOUBLE_EQ(m.x_s, 2.0 / 3.0);
  const auto after = contact_loads(c);
  EXPECT_NEAR(after[1].f_t, -mu * after[1].f_n, 1e-12);
  // Frictionless contacts are never "sliding".
  c.material.mu = 0.0;
  EXPECT_DOUBLE_EQ(measure(c).x_s, 0.0);
}

TEST(Measurements, TorqueMeasureFromTangentialForces) {
  Configuration c = triangle(false);
  const auto loads = contact_loads(c);
  // Contact 0 is 0-1 (horizontal): a tangential force there spins disks 0 and 1 alike.
  ASSERT_EQ(c.contacts.i[0], 0);
  ASSERT_EQ(c.contacts.j[0], 1);
  const double f_t = 3.0;
  c.contacts.delta_t[0] = -f_t / c.material.k_t;
  const Measurements m = measure(c);
  const double a = loads[0].frame.a_i;  // = a_j: equal radii
  EXPECT_NEAR(m.max_net_torque, a * f_t, 1e-12);
  EXPECT_NEAR(m.torque_2, std::sqrt(2.0 * (a * f_t) * (a * f_t) / 3.0), 1e-12);
}

TEST(Measurements, KineticEnergyStrainsAndQ) {
  Configuration c = pair_configuration({2.0, 2.0, 0, 0});
  c.disks.vx[0] = 0.3;
  c.disks.vy[0] = -0.4;
  c.disks.omega[1] = 2.0;
  const double e0 = 0.5 * c.disks.mass[0] * 0.25;
  const double e1 = 0.5 * c.disks.inertia[1] * 4.0;
  EXPECT_NEAR(kinetic_energy_per_disk(c.disks), (e0 + e1) / 2.0, 1e-15);
  EXPECT_DOUBLE_EQ(c.disks.inertia[1], 0.5 * 4.0 * 0.45 * 0.45 * 0.45 * 0.45);  // m d^2 / 8

  c.stage.reference_length = {5.1, 3.9};
  const auto eps = strains(c);
  EXPECT_NEAR(eps[0], 1.0 - 5.0 / 5.1, 1e-15);
  EXPECT_NEAR(eps[1], 1.0 - 4.0 / 3.9, 1e-15);
  EXPECT_NEAR(eps[2], 1.0 - 20.0 / (5.1 * 3.9), 1e-15);  // epsilon_v = 1 - A / A0

  const Measurements m = measure(c);
  EXPECT_NEAR(m.q, (m.sigma[1][1] - m.sigma[0][0]) / m.sigma[0][0], 1e-15);
  EXPECT_GT(m.q, 0.0);  // the branch is closer to the y axis: more axial stress
}

}  // namespace
}  // namespace granstab
