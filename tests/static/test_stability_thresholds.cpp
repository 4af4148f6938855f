// STATIC.md §S4 T4 (disk on a flat wall: limit point at T = mu F_N) and T5 (straight periodic
// chains under axial force: the rotation and period-length dependent stability thresholds).
#include <gtest/gtest.h>

#include <cmath>

#include "static/backbone.hpp"
#include "static/hill.hpp"
#include "static/linear_solvers.hpp"
#include "static/load_step.hpp"
#include "static/q1.hpp"

namespace granstab::statics {
namespace {

// A disk of radius 1/2 pressed on the bottom wall by a dead load N, rotation blocked; the dead
// load T along the wall is the load parameter.
Network disk_on_wall(double normal_load, double mu_wall) {
  Network net;
  net.boundary = Boundary::walls;
  net.length = {10.0, 10.0};
  net.material.k_n = 1e3;
  net.material.k_t = 600.0;
  net.material.mu = 0.5;
  net.material.mu_wall = mu_wall;
  net.x = {5.0};
  net.y = {0.5 - normal_load / net.material.k_n};
  net.radius = {0.5};
  net.theta = {0.0};
  net.contacts.add(0, wall_bottom, 0, 0);
  net.constraints.rotation_fixed = {1};
  net.constraints.cell_free = {false, false};
  net.constraints.remove_rattlers = false;  // one contact and a dead load: not a rattler
  net.loading.dead = {0.0, -normal_load, 0.0};
  return net;
}

TEST(DiskOnWall, LimitPointExactlyAtTheCoulombThreshold) {
  const double normal_load = 2.0, mu_wall = 0.3;
  Q1Options options;
  options.dq = 0.05;
  options.dq_min = 1e-8;
  const LoadPath tangential = [](Network& n, double t) { n.loading.dead[0] = t; };
  const StabilityResult r = trace_to_instability(disk_on_wall(normal_load, mu_wall), 0.0,
                                                 tangential, {10.0, 10.0}, options);
  const double limit = mu_wall * normal_load;
  EXPECT_EQ(r.criterion, Criterion::existence) << r.detail;
  EXPECT_LE(r.q1_bracket[0], limit);
  // A contact within sliding_tolerance (1e-9 relative) of the cone counts as critical (§S3.0), so
  // the state whose load sums to 0.6 in floating point one ulp short of mu N is already critical.
  EXPECT_GE(r.q1_bracket[1], limit * (1.0 - sliding_tolerance));
  EXPECT_LT(r.q1_bracket[1] - r.q1_bracket[0], 2.0 * options.dq_min);
  for (const CurvePoint& p : r.curve) EXPECT_EQ(p.n_sliding, 0);  // sticks all the way
  // The unstable mode is the slip of the disk along the wall.
  ASSERT_EQ(r.mode.size(), 3u);
  EXPECT_GT(std::abs(r.mode[0]), 0.999);
}

// N disks of radius 1/2 per period L1 = N d along x, d = 2R - F/K_N, axial stress sigma1 = F/L2,
// e2 fixed, e1 free under sigma1.
Network chain(int n, double force, double k_t, bool rotations_fixed) {
  Network net;
  net.boundary = Boundary::periodic;
  net.material.k_n = 1e3;
  net.material.k_t = k_t;
  net.material.mu = 0.5;
  const double d = 1.0 - force / net.material.k_n;
  net.length = {n * d, 3.0};
  for (int i = 0; i < n; ++i) {
    net.x.push_back(0.5 + i * d);
    net.y.push_back(1.5);
    net.radius.push_back(0.5);
    net.theta.push_back(0.0);
  }
  for (int i = 0; i + 1 < n; ++i) net.contacts.add(i, i + 1, 0, 0);
  net.contacts.add(n - 1, 0, 1, 0);
  net.constraints.cell_free = {true, false};
  if (rotations_fixed) net.constraints.rotation_fixed.assign(n, 1);
  net.loading.sigma = {force / net.length[1], 0.0};
  prepare(net, SolverOptions{});
  return net;
}

struct Stability {
  double hill;
  int pinned_rotations;
};

Stability stability(const Network& net) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  const std::vector<ContactStatus> statuses = classify_contacts(states);
  const std::vector<char> kept = kept_dofs(net, states, statuses);
  const SparseMatrix k = reduce(assemble_tangent(net, states, statuses), make_reduction(kept));
  const HillResult h = hill_indicator(k);
  EXPECT_TRUE(h.ok);
  // K is symmetric here (F_T = 0, e2 fixed): Hill > 0 is stability.
  EXPECT_LT((Eigen::MatrixXd(k) - Eigen::MatrixXd(k).transpose()).cwiseAbs().maxCoeff(), 1e-9);
  int pinned = 0;
  for (char c : kept) pinned += c ? 0 : 1;
  return {h.min_eigenvalue, pinned};
}

TEST(PeriodicChain, RotationsPinnedStableIffTangentialStiffnessExceedsFOverD) {
  const double force = 5.0, d = 1.0 - force / 1e3, threshold = force / d;
  for (int n : {2, 3, 5}) {
    EXPECT_GT(stability(chain(n, force, 1.01 * threshold, true)).hill, 0.0) << n;
    EXPECT_LT(stability(chain(n, force, 0.99 * threshold, true)).hill, 0.0) << n;
  }
}

TEST(PeriodicChain, RotationsFreeThreeOrMoreDisksRollForAnyForce) {
  for (int n : {3, 4, 6})
    for (double force : {1e-3, 5.0}) {
      const double d = 1.0 - force / 1e3;
      const Stability s = stability(chain(n, force, 100.0 * force / d, false));
      EXPECT_LT(s.hill, 0.0) << n << " " << force;
      // Even rings also carry the alternating gear mode, which is pinned; odd rings frustrate it.
      EXPECT_EQ(s.pinned_rotations, n % 2 == 0 ? 1 : 0) << n;
    }
}

TEST(PeriodicChain, TwoDisksTouchTwiceOnlyTheGearModeIsFree) {
  const double force = 5.0, d = 1.0 - force / 1e3, threshold = force / d;
  const Stability above = stability(chain(2, force, 1.01 * threshold, false));
  EXPECT_GT(above.hill, 0.0);
  EXPECT_EQ(above.pinned_rotations, 1);  // theta_1 = -theta_2, pinned as harmless
  EXPECT_LT(stability(chain(2, force, 0.99 * threshold, false)).hill, 0.0);
}

// Criterion (b) on the 2-disk chain with rotations pinned: raising the axial force F, the single
// transverse mode loses stability when K_T = F/d with d = 1 - F/K_N, i.e. at
// F* = K_T / (1 + K_T/K_N); det K changes sign there.
TEST(PeriodicChain, AxialLoadBifurcatesWhereTheTransverseStiffnessVanishes) {
  const double k_t = 50.0, k_n = 1e3, f_star = k_t / (1.0 + k_t / k_n);
  Network net = chain(2, 10.0, k_t, true);
  const double l2 = net.length[1];
  const LoadPath axial = [l2](Network& n, double force) { n.loading.sigma = {force / l2, 0.0}; };
  Q1Options o;
  o.dq = 1.0;
  o.dq_min = 1e-6;
  const StabilityResult r = trace_to_instability(net, 10.0, axial, net.length, o);
  EXPECT_EQ(r.criterion, Criterion::bifurcation) << r.detail;
  EXPECT_LE(r.q1_bracket[0], f_star);
  EXPECT_GE(r.q1_bracket[1], f_star);
  EXPECT_LT(r.q1_bracket[1] - r.q1_bracket[0], 2e-6);
  EXPECT_GT(r.curve.front().hill, 0.0);
  // The mode is the transverse displacement of the free disk.
  ASSERT_EQ(r.mode.size(), 6u);
  EXPECT_GT(std::abs(r.mode[4]), 0.999);
}

}  // namespace
}  // namespace granstab::statics
