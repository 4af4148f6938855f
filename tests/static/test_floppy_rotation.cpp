// STATIC.md §S3.5: a disk whose contacts all slide has a free rotation, which kept_dofs pins. Its
// torque row then constrains the translations alone, so under a generic load increment it is out
// of balance: that status set has no solution, and some contact must stick. The predictor used
// to report such a set as "singular" and end the stepping (q1 of series A at mu = 0.25,
// docs/validation.md, "Static q1: floppy rotations out of balance ...").
#include <gtest/gtest.h>

#include <cmath>

#include "static/backbone.hpp"
#include "static/load_step.hpp"
#include "static/q1.hpp"

namespace granstab::statics {
namespace {

// A disk of radius 1/2 in the bottom-left corner of a walled box, both wall contacts on the
// Coulomb cone (F_N = 1, |F_T| = mu_wall F_N, signs chosen so that the torques add) and held in
// equilibrium by a dead load (force and torque). Rotation free, walls fixed.
Network disk_in_corner() {
  Network net;
  net.boundary = Boundary::walls;
  net.length = {10.0, 10.0};
  net.material.k_n = 1e3;
  net.material.k_t = 500.0;
  net.material.mu = 0.5;
  net.material.mu_wall = 0.5;
  const double r = 0.5, h = 1.0 / net.material.k_n;  // F_N = K_N h = 1 on both walls
  net.x = {r - h};
  net.y = {r - h};
  net.radius = {r};
  net.theta = {0.0};
  // F_T = -K_T delta_t = +-mu F_N.
  net.contacts.add(0, wall_bottom, 0, 0, -0.5 / net.material.k_t);
  net.contacts.add(0, wall_left, 0, 0, -0.5 / net.material.k_t);
  net.constraints.cell_free = {false, false};
  net.constraints.remove_rattlers = false;  // two contacts and a dead load: not a rattler
  net.loading.dead = {0.0, 0.0, 0.0};
  rebuild_degrees_of_freedom(net);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const Eigen::VectorXd r0 = residual(net, zero, evaluate_contacts(net, zero));
  net.loading.dead = {-r0[net.dofs.ux[0]], -r0[net.dofs.uy[0]], -r0[net.dofs.theta[0]]};
  return net;
}

TEST(FloppyRotation, TheCornerDiskIsOnTheConeAtBothWallsWithItsTorqueCarried) {
  Network net = disk_in_corner();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  const std::vector<ContactStatus> statuses = classify_contacts(states);
  for (std::size_t c = 0; c < states.size(); ++c) {
    EXPECT_NEAR(states[c].f_n, 1.0, 1e-12);
    EXPECT_NE(statuses[c], ContactStatus::stick) << c;
  }
  EXPECT_NE(net.loading.dead[2], 0.0);  // the dead torque balances the two friction torques
  EXPECT_LT(residual(net, zero, states).cwiseAbs().maxCoeff(), 1e-12);
  // Both sliding: the rotation is floppy and pinned.
  EXPECT_FALSE(kept_dofs(net, states, statuses)[net.dofs.theta[0]]);
  EXPECT_EQ(sliding_contacts_of_gear_clusters(net, states, statuses, {0}),
            (std::vector<int>{0, 1}));
}

// The predictor on the pushed corner disk: without resolve_unbalanced_rows it reports the
// status set (both contacts sliding) as out of balance, not as a singular K; with it, the LCP of
// the two contacts makes one stick and the loop ends consistent.
TEST(FloppyRotation, PredictorSettlesTheUnbalancedRotationWhenAsked) {
  Network net = disk_in_corner();
  net.loading.dead[0] -= 0.01;
  SolverOptions options;
  const PredictorResult off = predict(net, options, nullptr, nullptr, nullptr, true);
  EXPECT_FALSE(off.ok);
  EXPECT_TRUE(off.unbalanced_rows);
  EXPECT_EQ(off.failure, "pinned rotation rows out of balance");
  options.resolve_unbalanced_rows = true;
  const PredictorResult on = predict(net, options, nullptr, nullptr, nullptr, true);
  ASSERT_TRUE(on.ok) << on.failure;
  EXPECT_GT(on.determinant_sign, 0);
  EXPECT_TRUE(on.statuses[0] == ContactStatus::stick || on.statuses[1] == ContactStatus::stick);
  EXPECT_TRUE(on.kept[net.dofs.theta[0]]);  // a sticking contact to a wall fixes the rotation
}

// Pushing the disk further into the left wall (dead force -x raised) loads the left contact, whose
// cone grows. With both contacts sliding the pinned torque row is out of balance (the friction
// torque changes with dF_N of the left contact, and no dof can balance it), so the consistent
// statuses have a contact sticking and the state is stable (both stick after the first step).
// Before the fix: "predictor at the start: singular", q1 = 0, criterion existence.
TEST(FloppyRotation, UnbalancedPinnedRotationIsNotAnInstability) {
  const Network net = disk_in_corner();
  const double fx0 = net.loading.dead[0];
  Q1Options options;
  options.dq = 0.05;
  options.hill_every = 0;
  options.load_stop = 0.5;
  const LoadPath push = [fx0](Network& n, double t) { n.loading.dead[0] = fx0 - t; };
  const StabilityResult r = trace_to_instability(net, 0.0, push, {10.0, 10.0}, options);
  EXPECT_EQ(r.criterion, Criterion::none) << r.q1 << " " << r.detail;
  ASSERT_GE(r.curve.size(), 2u);
  EXPECT_EQ(r.curve.front().n_sliding, 2);
  EXPECT_LT(r.curve.back().n_sliding, 2);  // the grown cones hold the friction forces
  EXPECT_GE(r.q1, 0.5);
}

// Raising the dead torque instead spins the disk: no status set carries it (sticking either
// contact puts its trial force outside the cone), a genuine loss of existence at the start, and
// the exact LCP of the two contacts proves it (it was reported as a singular K).
TEST(FloppyRotation, RaisedTorqueSpinsTheDisk) {
  const Network net = disk_in_corner();
  const double torque0 = net.loading.dead[2];
  Q1Options options;
  options.dq = 0.05;
  options.hill_every = 0;
  options.load_stop = 0.5;
  const LoadPath twist = [torque0](Network& n, double t) {
    n.loading.dead[2] = torque0 + std::copysign(t, torque0);
  };
  const StabilityResult r = trace_to_instability(net, 0.0, twist, {10.0, 10.0}, options);
  EXPECT_EQ(r.criterion, Criterion::existence);
  EXPECT_EQ(r.q1, 0.0);
  EXPECT_NE(r.detail.find("no consistent statuses"), std::string::npos) << r.detail;
}

}  // namespace
}  // namespace granstab::statics
