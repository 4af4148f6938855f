// Rigid-limit bound (SPEC §4.5, STATIC.md §S3.6): closed-form q_max of small networks, clean
// reports of unbounded and infeasible cases, and an independent optimality certificate (primal
// forces checked against balance and the cone, dual mechanism checked for admissibility: equal
// values prove optimality without trusting Ipopt).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

#include "common/configuration.hpp"
#include "common/contact_law.hpp"
#include "common/io/configuration_file.hpp"
#include "static/rigid_limit.hpp"

namespace granstab::statics {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double sqrt3 = std::numbers::sqrt3;

Configuration periodic_cell(double l1, double l2, double mu) {
  Configuration c;
  c.cell.boundary = Boundary::periodic;
  c.cell.length = {l1, l2};
  c.material.mu = mu;
  return c;
}

// Every overlapping pair (and disk-image pair) once: i < j with any image, or i == j with the
// image shift positive in lexicographic order.
void add_overlapping_contacts(Configuration& c) {
  const Disks& d = c.disks;
  for (int i = 0; i < static_cast<int>(d.size()); ++i)
    for (int j = i; j < static_cast<int>(d.size()); ++j)
      for (int k1 = -1; k1 <= 1; ++k1)
        for (int k2 = -1; k2 <= 1; ++k2) {
          if (i == j && (k1 < 0 || (k1 == 0 && k2 <= 0))) continue;
          const double lx = d.x[j] + k1 * c.cell.length[0] - d.x[i];
          const double ly = d.y[j] + k2 * c.cell.length[1] - d.y[i];
          if (disk_disk_frame(lx, ly, d.radius[i], d.radius[j]).h > 0.0)
            c.contacts.add(i, j, k1, k2);
        }
}

ContactFrame frame(const Configuration& c, std::size_t k) {
  const int i = c.contacts.i[k], j = c.contacts.j[k];
  const Disks& d = c.disks;
  if (is_wall(j)) return disk_wall_frame(d.x[i], d.y[i], d.radius[i], Wall(j), c.cell);
  return disk_disk_frame(d.x[j] + c.contacts.k1[k] * c.cell.length[0] - d.x[i],
                         d.y[j] + c.contacts.k2[k] * c.cell.length[1] - d.y[i], d.radius[i],
                         d.radius[j]);
}

// Independent check of a bounded result: the forces are admissible and balance sigma_1 = P,
// sigma_2 = P (1 + q_max); the mechanism is admissible (g_N >= mu |g_T| on every contact of the
// LP) and its virtual work gives the bound q <= e_1 - 1 (e_2 = -1) for every admissible force
// set. Equality of the two certifies q_max as the optimum.
void expect_certified(const Configuration& c, const RigidLimitResult& r, double tol) {
  ASSERT_TRUE(r.solved) << r.status;
  ASSERT_TRUE(r.bounded) << r.status;
  const std::size_t n = c.disks.size();
  std::vector<double> fx(n, 0.0), fy(n, 0.0), torque(n, 0.0);
  std::vector<int> loaded(n, 0);
  double a_sigma1 = 0.0, a_sigma2 = 0.0;
  for (std::size_t k = 0; k < c.contacts.size(); ++k) {
    const ContactFrame f = frame(c, k);
    const int i = c.contacts.i[k], j = c.contacts.j[k];
    const double mu = is_wall(j) ? c.material.mu_wall : c.material.mu;
    EXPECT_GE(r.f_n[k], 0.0);
    EXPECT_LE(std::abs(r.f_t[k]), mu * r.f_n[k] + 1e-14);
    if (!r.in_lp[k]) {
      EXPECT_EQ(r.f_n[k], 0.0);
      continue;
    }
    const double gx = r.f_n[k] * f.nx + r.f_t[k] * f.tx, gy = r.f_n[k] * f.ny + r.f_t[k] * f.ty;
    fx[i] -= gx, fy[i] -= gy, torque[i] -= f.a_i * r.f_t[k], loaded[i] = 1;
    double ujx = 0.0, ujy = 0.0, theta_j = 0.0;
    double wall_e1 = 0.0, wall_e2 = 0.0;  // wall velocity of the mechanism
    if (!is_wall(j)) {
      fx[j] += gx, fy[j] += gy, torque[j] -= f.a_j * r.f_t[k], loaded[j] = 1;
      ujx = r.mechanism_ux[j], ujy = r.mechanism_uy[j], theta_j = r.mechanism_theta[j];
      if (c.cell.periodic()) {
        a_sigma1 += f.lx * gx;
        a_sigma2 += f.ly * gy;
        wall_e1 = r.mechanism_e[0] * f.lx;  // affine part of the relative motion
        wall_e2 = r.mechanism_e[1] * f.ly;
      }
    } else if (j == wall_right) {
      a_sigma1 += c.cell.length[0] * gx;
      wall_e1 = r.mechanism_e[0] * c.cell.length[0];
    } else if (j == wall_top) {
      a_sigma2 += c.cell.length[1] * gy;
      wall_e2 = r.mechanism_e[1] * c.cell.length[1];
    }
    const double dvx = ujx - r.mechanism_ux[i] + wall_e1, dvy = ujy - r.mechanism_uy[i] + wall_e2;
    const double g_n = -deflection_rate(f, dvx, dvy);
    const double g_t = tangential_rate(f, dvx, dvy, r.mechanism_theta[i], theta_j);
    EXPECT_GE(g_n - mu * std::abs(g_t), -tol) << "contact " << k;
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!loaded[i]) continue;
    EXPECT_NEAR(fx[i], 0.0, 1e-8) << "disk " << i;
    EXPECT_NEAR(fy[i], 0.0, 1e-8) << "disk " << i;
    EXPECT_NEAR(torque[i], 0.0, 1e-8) << "disk " << i;
  }
  EXPECT_NEAR(a_sigma1 / c.cell.area(), 1.0, 1e-8);
  const double scale = std::max(1.0, std::abs(r.q_max));
  EXPECT_NEAR(a_sigma2 / c.cell.area(), 1.0 + r.q_max, 1e-8 * scale);
  EXPECT_LE(r.max_residual, 1e-8);
  EXPECT_DOUBLE_EQ(r.mechanism_e[1], -1.0);
  EXPECT_NEAR(r.mechanism_e[0] - 1.0, r.q_max, tol * scale);  // weak duality gap
}

// Two equal disks per L1 x L2 cell forming a rhombic lattice: contacts along +-phi only
// (30 < phi < 60 degrees keeps the images along the axes apart).
Configuration rhombic_lattice(double phi, double mu) {
  const double radius = 0.5, d = 2 * radius - 1e-4;
  Configuration c = periodic_cell(2 * d * std::cos(phi), 2 * d * std::sin(phi), mu);
  c.disks.add(0.1, 0.2, radius);
  c.disks.add(0.1 + d * std::cos(phi), 0.2 + d * std::sin(phi), radius);
  add_overlapping_contacts(c);
  return c;
}

// Rhombic lattice: by the mirror (x -> -x) and disk-swap symmetries an optimal force set has
// F_N equal on all contacts and F_T = +-tau F_N, torques balancing pairwise; then
// sigma_2 / sigma_1 = tan(phi) (tan(phi) + tau) / (1 - tau tan(phi)), largest at tau = mu:
// q_max = tan(phi) tan(phi + psi) - 1 with the friction angle psi = atan(mu), unbounded once
// phi + psi >= 90 degrees (sigma_1 can then vanish).
TEST(RigidLimit, RhombicLatticeFrictionAngle) {
  for (const double phi_deg : {40.0, 50.0}) {
    for (const double mu : {0.0, 0.1, 0.3}) {
      const double phi = phi_deg * pi / 180.0;
      const Configuration c = rhombic_lattice(phi, mu);
      ASSERT_EQ(c.contacts.size(), 4u);
      const RigidLimitResult r = rigid_limit(c);
      const double expected = std::tan(phi) * std::tan(phi + std::atan(mu)) - 1.0;
      EXPECT_NEAR(r.q_max, expected, 1e-7 * (1.0 + expected))
          << "phi " << phi_deg << " mu " << mu << " status " << r.status;
      expect_certified(c, r, 1e-7);
    }
  }
}

TEST(RigidLimit, RhombicLatticeBeyondFrictionAngleIsUnbounded) {
  const RigidLimitResult r = rigid_limit(rhombic_lattice(50.0 * pi / 180.0, 1.5));
  EXPECT_TRUE(r.solved) << r.status;
  EXPECT_FALSE(r.bounded);
  EXPECT_EQ(r.status, "unbounded");
  EXPECT_TRUE(std::isinf(r.q_max) && r.q_max > 0.0);
  EXPECT_TRUE(r.f_n.empty());
}

// Triangular lattice, two equal disks per d x sqrt(3) d cell: contacts at 0, 60, 120 degrees.
// The horizontal contacts only add to sigma_1, so the optimum has F_N = 0 there and the
// rhombic result at phi = 60 degrees holds: q_max = 2 (1 + sqrt3 mu) / (1 - sqrt3 mu)
// (q_max = 2, i.e. sigma_2 / sigma_1 = tan^2 60, without friction), unbounded for mu >= 1/sqrt3.
Configuration triangular_lattice(double mu) {
  const double radius = 0.5, d = 2 * radius - 1e-4;
  Configuration c = periodic_cell(d, sqrt3 * d, mu);
  c.disks.add(0.3, 0.2, radius);
  c.disks.add(0.3 + 0.5 * d, 0.2 + 0.5 * sqrt3 * d, radius);
  add_overlapping_contacts(c);
  return c;
}

TEST(RigidLimit, TriangularLattice) {
  for (const double mu : {0.0, 0.1, 0.3, 0.5}) {
    const Configuration c = triangular_lattice(mu);
    ASSERT_EQ(c.contacts.size(), 6u);
    const RigidLimitResult r = rigid_limit(c);
    const double expected = 2.0 * (1.0 + sqrt3 * mu) / (1.0 - sqrt3 * mu);
    EXPECT_NEAR(r.q_max, expected, 1e-7 * (1.0 + expected)) << "mu " << mu << " " << r.status;
    expect_certified(c, r, 1e-7);
  }
  const RigidLimitResult r = rigid_limit(triangular_lattice(0.7));
  EXPECT_TRUE(r.solved) << r.status;
  EXPECT_TRUE(std::isinf(r.q_max));
}

// Square lattice, contacts along x and y: normal forces alone carry any sigma_1, sigma_2 >= 0,
// so sigma_1 -> 0 at fixed sigma_2 is admissible and q is unbounded, with or without friction.
// The 2 x 2 version has a gear mode (theta alternating on the bipartite lattice), i.e.
// dependent torque rows: the solver must still answer.
Configuration square_lattice(int m, double mu) {
  const double radius = 0.5, d = 2 * radius - 1e-4;
  Configuration c = periodic_cell(m * d, m * d, mu);
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) c.disks.add((a + 0.5) * d, (b + 0.5) * d, radius);
  add_overlapping_contacts(c);
  return c;
}

TEST(RigidLimit, SquareLatticeIsUnbounded) {
  for (const int m : {1, 2})
    for (const double mu : {0.0, 0.3}) {
      const Configuration c = square_lattice(m, mu);
      ASSERT_EQ(c.contacts.size(), static_cast<std::size_t>(2 * m * m));
      const RigidLimitResult r = rigid_limit(c);
      EXPECT_TRUE(r.solved) << "m " << m << " mu " << mu << " " << r.status;
      EXPECT_EQ(r.status, "unbounded");
      EXPECT_TRUE(std::isinf(r.q_max) && r.q_max > 0.0);
    }
}

// Walled cell, frictionless disk-disk contact, wall friction mu_w. Disk A sits in the fixed
// (left, bottom) corner, disk B in the mobile (right, top) corner, the branch A -> B at angle
// phi > 45 degrees, equal overlaps (equal lever arms). B: N_R = N cos - T_R, N_T = N sin - T_R,
// torque T_R + T_T = 0, cones |T_R| <= mu_w N_R (binding), |T_T| <= mu_w N_T; A is balanced by
// the fixed walls without friction. With sigma_1 L_2 = N_R, sigma_2 L_1 = N_T:
// q_max = (L_2 / L_1) (tan(phi) (1 + mu_w) - mu_w) - 1. With frictionless walls B cannot carry a
// tangential contact force (torque), so the disk-disk mu does not matter. A third, small disk
// touching B only must not change anything.
Configuration two_disks_in_walls(double phi, double mu, double mu_wall) {
  const double radius = 0.5, h = 1e-3, d = 2 * radius - h;
  Configuration c;
  c.cell.boundary = Boundary::walls;
  c.cell.length = {2 * radius - 2 * h + d * std::cos(phi), 2 * radius - 2 * h + d * std::sin(phi)};
  c.material.mu = mu;
  c.material.mu_wall = mu_wall;
  const int a = static_cast<int>(c.disks.add(radius - h, radius - h, radius));
  const int b = static_cast<int>(
      c.disks.add(c.cell.length[0] - radius + h, c.cell.length[1] - radius + h, radius));
  c.contacts.add(a, wall_left, 0, 0);
  c.contacts.add(a, wall_bottom, 0, 0);
  c.contacts.add(a, b, 0, 0);
  c.contacts.add(b, wall_right, 0, 0);
  c.contacts.add(b, wall_top, 0, 0);
  // A small disk touching B only: one contact cannot balance, so it carries no force.
  const int weak =
      static_cast<int>(c.disks.add(c.disks.x[b] - (radius + 0.1 - h), c.disks.y[b], 0.1));
  c.contacts.add(weak, b, 0, 0);
  return c;
}

TEST(RigidLimit, TwoDisksBetweenWalls) {
  struct Case {
    double phi_deg, mu, mu_wall;
  };
  for (const Case k :
       {Case{60, 0.0, 0.0}, Case{60, 0.4, 0.0}, Case{60, 0.0, 0.3}, Case{55, 0.0, 0.5}}) {
    const double phi = k.phi_deg * pi / 180.0;
    const Configuration c = two_disks_in_walls(phi, k.mu, k.mu_wall);
    for (std::size_t n = 0; n < c.contacts.size(); ++n) ASSERT_GT(frame(c, n).h, 0.0);
    const RigidLimitResult r = rigid_limit(c);
    EXPECT_EQ(r.n_disks, 2u);
    EXPECT_EQ(r.n_contacts, 5u);
    EXPECT_FALSE(r.in_lp[5]);
    const double ratio = c.cell.length[1] / c.cell.length[0];
    const double expected = ratio * (std::tan(phi) * (1 + k.mu_wall) - k.mu_wall) - 1.0;
    EXPECT_NEAR(r.q_max, expected, 1e-7 * (1.0 + expected))
        << "phi " << k.phi_deg << " mu " << k.mu << " mu_wall " << k.mu_wall << " " << r.status;
    expect_certified(c, r, 1e-7);
  }
}

// A disk squeezed between the bottom and top walls only: nothing reaches the right wall, so no
// force set has sigma_1 > 0: the LP is infeasible and must say so, not return a number.
TEST(RigidLimit, NothingOnRightWallIsInfeasible) {
  Configuration c;
  c.cell.boundary = Boundary::walls;
  c.cell.length = {3.0, 0.999};
  c.material.mu_wall = 0.2;
  c.disks.add(1.5, 0.4995, 0.5);
  c.contacts.add(0, wall_bottom, 0, 0);
  c.contacts.add(0, wall_top, 0, 0);
  const RigidLimitResult r = rigid_limit(c);
  EXPECT_FALSE(r.solved);
  EXPECT_TRUE(std::isnan(r.q_max));
  EXPECT_EQ(r.status.rfind("infeasible", 0), 0u) << r.status;

  Configuration empty = periodic_cell(5.0, 5.0, 0.3);
  empty.disks.add(1.0, 1.0, 0.5);
  const RigidLimitResult none = rigid_limit(empty);
  EXPECT_FALSE(none.solved);
  EXPECT_EQ(none.status.rfind("infeasible", 0), 0u) << none.status;
}

// A periodic zigzag chain, two equal disks per cell, contacts at +theta and 180 - theta degrees.
// Each disk has two contacts, so both forces lie on the chord through its contact points; all
// contact points lie on one horizontal line, so the chain carries a horizontal force iff the
// cones allow it, mu >= tan(theta). Then sigma_2 = 0 exactly: q_max = -1. Otherwise no force
// set exists at all.
Configuration zigzag_chain(double theta, double mu) {
  const double radius = 0.5, d = 2 * radius - 1e-4;
  Configuration c = periodic_cell(2 * d * std::cos(theta), 3.0, mu);
  c.disks.add(0.2, 1.0, radius);
  c.disks.add(0.2 + d * std::cos(theta), 1.0 + d * std::sin(theta), radius);
  add_overlapping_contacts(c);
  return c;
}

TEST(RigidLimit, ZigzagChainNeedsFrictionAngle) {
  const double theta = 20.0 * pi / 180.0;  // tan(theta) = 0.364
  const Configuration carried = zigzag_chain(theta, 0.5);
  ASSERT_EQ(carried.contacts.size(), 2u);
  const RigidLimitResult r = rigid_limit(carried);
  EXPECT_NEAR(r.q_max, -1.0, 1e-8) << r.status;
  expect_certified(carried, r, 1e-7);

  const RigidLimitResult none = rigid_limit(zigzag_chain(theta, 0.3));
  EXPECT_FALSE(none.solved);
  EXPECT_TRUE(std::isnan(none.q_max));
  EXPECT_EQ(none.status.rfind("infeasible", 0), 0u) << none.status;
}

// A disordered network: a jittered triangular lattice of polydisperse disks (some neighbour
// pairs open, plus a listed contact with h <= 0). Not too dilute: chains of two-contact disks
// carry force only if their contact points are exactly collinear, so a strongly diluted
// jittered lattice is (correctly) infeasible.
Configuration disordered_packing(unsigned seed, double mu) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.03, 0.03), radius(0.48, 0.56);
  const int m = 6;
  const double d = 0.97;
  Configuration c = periodic_cell(m * d, m * sqrt3 * d, mu);
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < 2 * m; ++b)
      c.disks.add((a + 0.5 * (b % 2) + 0.25) * d + jitter(rng),
                  (b + 0.5) * 0.5 * sqrt3 * d + jitter(rng), radius(rng));
  add_overlapping_contacts(c);
  c.contacts.add(0, 6, 0, 0);  // an open pair kept in the list: not part of the network
  return c;
}

TEST(RigidLimit, DisorderedNetworkIsCertifiedOptimal) {
  for (const double mu : {0.2, 0.3}) {
    const Configuration c = disordered_packing(7, mu);
    const RigidLimitResult r = rigid_limit(c);
    ASSERT_TRUE(r.bounded) << r.status;
    EXPECT_LT(r.n_contacts, c.contacts.size());  // the open contact is not in the network
    EXPECT_GT(r.n_contacts, c.contacts.size() / 2);
    EXPECT_GT(r.q_max, 0.0);
    expect_certified(c, r, 1e-6);
    // Forces are returned for sigma_1 = options.sigma1; q_max does not depend on it.
    RigidLimitOptions twice;
    twice.sigma1 = 2.0;
    const RigidLimitResult r2 = rigid_limit(c, twice);
    EXPECT_NEAR(r2.q_max, r.q_max, 1e-7 * (1.0 + r.q_max));
    // The residual guard turns an inaccurate answer into a reported failure.
    RigidLimitOptions strict;
    strict.residual_limit = 0.1 * r.max_residual;
    ASSERT_GT(r.max_residual, 0.0);
    const RigidLimitResult r3 = rigid_limit(c, strict);
    EXPECT_FALSE(r3.solved);
    EXPECT_TRUE(std::isnan(r3.q_max));
    EXPECT_EQ(r3.status.rfind("inaccurate", 0), 0u) << r3.status;
  }
}

// The shipped sample (isotropic MD equilibrium, mu_prep = 0.15): its own contact forces balance
// q = 0 within the cone (to the SPEC §3.1 tolerances), so q_max >= 0 at mu = 0.15; larger cones
// can only raise q_max. Frictionless, the z = 3.5 network is hypostatic: a failure, reported.
TEST(RigidLimit, ShippedSample) {
  Configuration c = read_configuration(std::filesystem::path(GRANSTAB_SOURCE_DIR) /
                                       "data/samples/periodic-n100-k1e4.granstab");
  double previous = 0.0;
  for (const double mu : {0.15, 0.3, 0.5}) {
    c.material.mu = mu;
    const RigidLimitResult r = rigid_limit(c);
    EXPECT_GE(r.q_max, previous) << "mu " << mu << " " << r.status;
    expect_certified(c, r, 1e-6);
    previous = r.q_max;
  }
  c.material.mu = 0.0;
  const RigidLimitResult frictionless = rigid_limit(c);
  EXPECT_FALSE(frictionless.solved);
  EXPECT_TRUE(std::isnan(frictionless.q_max));
}

// Debian's sequential MUMPS aborts on concurrent use: the mutex inside rigid_limit() must make
// concurrent calls safe and give the serial answers.
TEST(RigidLimit, ConcurrentCallsAreSerialised) {
  const Configuration c1 = disordered_packing(11, 0.25), c2 = triangular_lattice(0.2);
  const double q1 = rigid_limit(c1).q_max, q2 = rigid_limit(c2).q_max;
  std::vector<RigidLimitResult> out1(4), out2(4);
  std::thread t1([&] {
    for (auto& r : out1) r = rigid_limit(c1);
  });
  std::thread t2([&] {
    for (auto& r : out2) r = rigid_limit(c2);
  });
  t1.join();
  t2.join();
  for (const auto& r : out1) {
    EXPECT_TRUE(r.solved) << r.status;
    EXPECT_EQ(r.q_max, q1);
  }
  for (const auto& r : out2) {
    EXPECT_TRUE(r.solved) << r.status;
    EXPECT_EQ(r.q_max, q2);
  }
}

TEST(RigidLimit, RejectsInconsistentInput) {
  Configuration c = triangular_lattice(0.3);
  c.contacts.add(0, wall_right, 0, 0);
  EXPECT_THROW(rigid_limit(c), std::invalid_argument);
  Configuration d = triangular_lattice(0.3);
  d.contacts.add(0, 5, 0, 0);
  EXPECT_THROW(rigid_limit(d), std::invalid_argument);
  RigidLimitOptions bad;
  bad.sigma1 = 0.0;
  EXPECT_THROW(rigid_limit(triangular_lattice(0.3), bad), std::invalid_argument);
}

}  // namespace
}  // namespace granstab::statics
