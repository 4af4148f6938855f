// The engine's use of the common contact law (SPEC §1.1): incremental tangential force with
// Coulomb slip, lever arms, objectivity under rigid rotation, periodic images.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "common/contact_law.hpp"
#include "dynamic/spatial_order.hpp"
#include "helpers.hpp"

namespace granstab {
namespace {

constexpr double heavy = 1e15;  // mass and inertia of disks that must keep their velocities

// Two disks of radius 1/2 overlapping by h along x in a large periodic cell; zeta = 0.
Configuration pair(double h, double mu, double kt_over_kn = 1.0, double mass = heavy) {
  const Material m = Material::from_kappa(1e4, kt_over_kn, mu, 0.0);
  Configuration c = testing::empty_periodic(20.0, 20.0, m);
  c.disks.add(10.0, 10.0, 0.5);
  c.disks.add(11.0 - h, 10.0, 0.5);
  for (std::size_t i = 0; i < 2; ++i) {
    c.disks.mass[i] = mass;
    c.disks.inertia[i] = mass;
  }
  return c;
}

TEST(TangentialLaw, StickThenSlideUnderTangentialPush) {
  const double h = 0.01, mu = 0.5, kt_over_kn = 0.5, v = 1e-3;
  Configuration c = pair(h, mu, kt_over_kn);
  c.disks.vy[1] = v;  // j pushed along t = (0, 1) relative to i (held by its huge mass)
  Engine e(c);
  e.set_dt(1e-3);
  const double k_n = 1e4, k_t = kt_over_kn * k_n;
  const double u_slip = mu * k_n * h / k_t;  // tangential displacement at the Coulomb limit
  bool slid = false;
  while (e.time() < 2.0 * u_slip / v) {
    e.step();
    const Configuration out = e.configuration();
    ASSERT_EQ(out.contacts.size(), 1u);
    const double u_t = v * e.time();
    const double f_t = -k_t * out.contacts.delta_t[0];  // along t, of i on j
    const double d = std::hypot(e.x()[1] - e.x()[0], e.y()[1] - e.y()[0]);
    const double f_n = k_n * (1.0 - d);
    // The force on j is F_N n + F_T t (n turns by u_t / d as j passes by).
    const double nx = (e.x()[1] - e.x()[0]) / d, ny = (e.y()[1] - e.y()[0]) / d;
    ASSERT_NEAR(e.force_x(1), f_n * nx - f_t * ny, 1e-9 * f_n);
    ASSERT_NEAR(e.force_y(1), f_n * ny + f_t * nx, 1e-9 * f_n);
    if (u_t < 0.99 * u_slip) {
      // Sticking: F_T = -K_T u_T (the spring resists the relative motion).
      ASSERT_NEAR(f_t, -k_t * u_t, 1e-3 * k_t * u_t) << "t = " << e.time();
      ASSERT_EQ(out.contacts.status[0], ContactStatus::stick);
    } else if (u_t > 1.01 * u_slip) {
      // Sliding: |F_T| = mu F_N with the elastic F_N of the current overlap.
      ASSERT_NEAR(f_t, -mu * f_n, 1e-9 * f_n);
      ASSERT_EQ(out.contacts.status[0], ContactStatus::slide_negative);
      slid = true;
    }
  }
  EXPECT_TRUE(slid);
}

TEST(TangentialLaw, SpinUsesLeverArmRMinusHalfH) {
  // Disk j spins; its contact point moves by -a_j omega t along t, a_j = R - h/2.
  const double h = 0.02, mu = 0.4, omega = 0.01;
  Configuration c = pair(h, mu);
  c.disks.omega[1] = omega;
  Engine e(c);
  e.set_dt(1e-2);
  const double a_j = 0.5 - 0.5 * h;
  e.run(100);
  const double u_t = -a_j * omega * e.time();
  EXPECT_NEAR(e.force_y(1), -1e4 * u_t, 1e-9 * 1e4 * std::abs(u_t));
  const double f_t = e.force_y(1);
  EXPECT_NEAR(e.torque(1), -a_j * f_t, 1e-12 * std::abs(f_t));  // torque of the contact on j
  EXPECT_NEAR(e.torque(0), -(0.5 - 0.5 * h) * f_t, 1e-12 * std::abs(f_t));
}

TEST(TangentialLaw, RigidRotationOfAPairIsObjective) {
  const double h = 0.01, omega = 1e-2;
  for (bool translate : {true, false}) {
    Configuration c = pair(h, 10.0);  // mu large enough that nothing slides
    const double cx = 0.5 * (c.disks.x[0] + c.disks.x[1]), cy = c.disks.y[0];
    for (std::size_t i = 0; i < 2; ++i) {
      c.disks.omega[i] = omega;
      if (translate) {  // rigid-body velocity field omega z x (r - c)
        c.disks.vx[i] = -omega * (c.disks.y[i] - cy);
        c.disks.vy[i] = omega * (c.disks.x[i] - cx);
      }
    }
    Engine e(c);
    e.set_dt(1e-2);
    e.run(500);  // a 0.05 rad turn, with constant (straight-line) velocities
    const double turned = omega * e.time();
    const double d = 1.0 - h;
    const double non_objective = 1e4 * d * turned;  // |F_T| if the pair's rotation were missed
    const double f_t =
        std::hypot(e.force_x(1), e.force_y(1)) > 0.0
            ? (-e.force_x(1) * (e.y()[1] - e.y()[0]) + e.force_y(1) * (e.x()[1] - e.x()[0])) /
                  std::hypot(e.x()[1] - e.x()[0], e.y()[1] - e.y()[0])
            : 0.0;
    if (translate) {
      // Straight-line motion departs from the circle at O(turned^3): |F_T| stays below
      // 1e-3 of what a frame that does not rotate with the contact would give.
      EXPECT_LT(std::abs(f_t), 1e-3 * non_objective);
    } else {
      // Spinning disks without the pair turning do load the contact: (a_i + a_j) = d.
      EXPECT_NEAR(std::abs(f_t), non_objective, 1e-6 * non_objective);
    }
  }
}

// The same moving, sliding, damped pair placed inside the cell and across each boundary.
struct PairRun {
  double lx, ly, vx, vy, omega_i, omega_j, fx, fy, torque, delta_t;
};

PairRun run_pair(double shift_x, double shift_y) {
  Material m = Material::from_kappa(1e4, 1.0, 0.3, 0.5);
  const double l = 12.0;
  Configuration c = testing::empty_periodic(l, l, m);
  const double x0 = 5.0 + shift_x, y0 = 6.0 + shift_y;
  c.disks.add(std::fmod(x0, l), std::fmod(y0, l), 0.45);
  c.disks.add(std::fmod(x0 + 0.7, l), std::fmod(y0 + 0.635, l), 0.5);  // h = 0.005
  c.disks.vx = {0.01, -0.02};
  c.disks.vy = {0.015, -0.01};
  c.disks.omega = {3.0, -2.0};
  const int k1 = c.disks.x[1] < c.disks.x[0] ? 1 : 0, k2 = c.disks.y[1] < c.disks.y[0] ? 1 : 0;
  c.contacts.add(0, 1, k1, k2, 2e-4);
  Engine e(c);
  e.run(20);  // a fraction of the contact duration: still touching
  const Configuration out = e.configuration();
  EXPECT_EQ(out.contacts.size(), 1u);
  EXPECT_NE(out.contacts.status.at(0), ContactStatus::stick);  // the spins make it slide
  double lx = e.x()[1] - e.x()[0], ly = e.y()[1] - e.y()[0];
  lx -= l * std::nearbyint(lx / l);
  ly -= l * std::nearbyint(ly / l);
  return {lx,           ly,           e.vx()[1],    e.vy()[1],   e.omega()[0],
          e.omega()[1], e.force_x(1), e.force_y(1), e.torque(1), out.contacts.delta_t.at(0)};
}

TEST(PeriodicImages, PairAcrossBoundariesEqualsPairInside) {
  const PairRun inside = run_pair(0.0, 0.0);
  ASSERT_NE(inside.delta_t, 0.0);
  // 6.8: j across x = L; 5.8: across y = L; both: the corner.
  for (auto [sx, sy] : {std::pair{6.8, 0.0}, std::pair{0.0, 5.8}, std::pair{6.8, 5.8}}) {
    const PairRun r = run_pair(sx, sy);
    const double tol = 1e-9;
    EXPECT_NEAR(r.lx, inside.lx, tol);
    EXPECT_NEAR(r.ly, inside.ly, tol);
    EXPECT_NEAR(r.vx, inside.vx, tol);
    EXPECT_NEAR(r.vy, inside.vy, tol);
    EXPECT_NEAR(r.omega_i, inside.omega_i, tol);
    EXPECT_NEAR(r.omega_j, inside.omega_j, tol);
    EXPECT_NEAR(r.fx, inside.fx, tol);
    EXPECT_NEAR(r.fy, inside.fy, tol);
    EXPECT_NEAR(r.torque, inside.torque, tol);
    EXPECT_NEAR(r.delta_t, inside.delta_t, 1e-12);
  }
}

}  // namespace
}  // namespace granstab

namespace granstab {
namespace {

TEST(ExternalForces, ConstantForceGivesUniformAcceleration) {
  Configuration c = testing::empty_periodic(20.0, 20.0, Material::from_kappa(1e4, 1.0, 0.5, 1.0));
  c.disks.add(5.0, 5.0, 0.5);
  c.disks.add(15.0, 15.0, 0.25);
  Engine e(c);
  const std::vector<double> fx{0.3, -0.1}, fy{0.0, 0.2};
  e.set_external_forces(fx, fy);
  EXPECT_DOUBLE_EQ(e.force_x(0), 0.3);
  e.run(1000);
  const double t = e.time();
  for (int i = 0; i < 2; ++i) {
    // Velocity Verlet is exact for a constant force.
    EXPECT_NEAR(e.vx()[i], fx[i] / c.disks.mass[i] * t, 1e-12);
    EXPECT_NEAR(e.vy()[i], fy[i] / c.disks.mass[i] * t, 1e-12);
  }
  EXPECT_NEAR(e.x()[1], 15.0 + 0.5 * fx[1] / c.disks.mass[1] * t * t, 1e-10);
  e.clear_external_forces();
  EXPECT_EQ(e.force_x(0), 0.0);
  EXPECT_THROW(e.set_external_forces(std::vector<double>{1.0}, fy), std::invalid_argument);
}

}  // namespace
}  // namespace granstab

namespace granstab {
namespace {

// The per-disk sums of the engine's pair passes (forces added as the rows are swept; a pair
// across two threads' parts added to i by its row and to j by its mirror) against a direct sum
// over the exported contacts with the contact law: F_N = K_N h, F_T = -K_T delta_t,
// F_v = alpha dh/dt with the final velocities. Randomly numbered disks, so that with two
// threads many pairs cross the parts; or, with `ordered`, more disks numbered in space, so that
// most blocks take the plain sweep and only a few near the part boundary check for crossings.
void expect_brute_force_sums(int threads, bool ordered = false) {
  const Material material = Material::from_kappa(1e3, 1.0, 0.3, 0.7);
  Configuration c = testing::random_gas(ordered ? 1500 : 300, 0.2, material, 5);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> velocity(-0.5, 0.5);
  for (std::size_t i = 0; i < c.disks.size(); ++i) {
    c.disks.radius[i] *= 1.9;  // solid fraction ~0.72: many overlaps
    c.disks.mass[i] = c.disks.radius[i] * c.disks.radius[i];
    c.disks.inertia[i] = 0.5 * c.disks.mass[i] * c.disks.radius[i] * c.disks.radius[i];
    c.disks.vx[i] = velocity(rng);
    c.disks.vy[i] = velocity(rng);
    c.disks.omega[i] = velocity(rng);
  }
  if (ordered) c = renumbered(c, spatial_order(c));
  omp_set_num_threads(threads);
  EngineOptions options;
  options.parallel_min_disks = 0;  // the team runs even these few disks
  Engine e(c, options);
  e.run(40);
  const Configuration s = e.configuration();
  const std::size_t n = s.disks.size();
  std::vector<double> fx(n, 0.0), fy(n, 0.0), torque(n, 0.0);
  double scale = 0.0;
  ASSERT_GT(s.contacts.size(), n / 2);
  for (std::size_t k = 0; k < s.contacts.size(); ++k) {
    const int i = s.contacts.i[k], j = s.contacts.j[k];
    double lx = s.disks.x[j] - s.disks.x[i], ly = s.disks.y[j] - s.disks.y[i];
    lx += s.cell.length[0] * minimum_image_shift(lx, s.cell.length[0]);
    ly += s.cell.length[1] * minimum_image_shift(ly, s.cell.length[1]);
    const ContactFrame f = disk_disk_frame(lx, ly, s.disks.radius[i], s.disks.radius[j]);
    const double h_rate =
        deflection_rate(f, s.disks.vx[j] - s.disks.vx[i], s.disks.vy[j] - s.disks.vy[i]);
    const double f_n = material.k_n * f.h, f_t = -material.k_t * s.contacts.delta_t[k];
    const double f_v = material.damping_coefficient(s.disks.mass[i], s.disks.mass[j]) * h_rate;
    const double ex = (f_n + f_v) * f.nx + f_t * f.tx, ey = (f_n + f_v) * f.ny + f_t * f.ty;
    fx[j] += ex;
    fy[j] += ey;
    fx[i] -= ex;
    fy[i] -= ey;
    torque[i] -= f.a_i * f_t;
    torque[j] -= f.a_j * f_t;
    scale = std::max(scale, f_n);
  }
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_NEAR(e.force_x(i), fx[i], 1e-10 * scale) << "disk " << i;
    ASSERT_NEAR(e.force_y(i), fy[i], 1e-10 * scale) << "disk " << i;
    ASSERT_NEAR(e.torque(i), torque[i], 1e-10 * scale) << "disk " << i;
  }
}

TEST(PairSums, MatchDirectSumOneThread) { expect_brute_force_sums(1); }
TEST(PairSums, MatchDirectSumTwoThreads) { expect_brute_force_sums(2); }
TEST(PairSums, MatchDirectSumTwoThreadsSpatialOrder) { expect_brute_force_sums(2, true); }

}  // namespace
}  // namespace granstab
