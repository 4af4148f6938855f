// A disk whose contacts all open under the status loop's statuses loses its dofs (kept_dofs); if
// the load increment puts a force on it, its dropped rows are out of balance and those statuses
// have no solution. At the step floor a step's predictor lets the disk go and the corrector, on
// the full equilibrium, decides whether its contacts close; the stability check keeps the failure
// (docs/static.md §S3.5). Before, such a set at the floor ended the stepping as an instability:
// series B stopped at q = 0.1785 and 0.1417 instead of 0.1804 after a round-off change.
#include <gtest/gtest.h>

#include <cmath>

#include "static/backbone.hpp"
#include "static/load_step.hpp"

namespace granstab::statics {
namespace {

// Two disks of radius 1/2 in the bottom corners of a fixed walled box, each pressed on its two
// walls (F_N = 1, no tangential force) by a dead load that balances the contact forces.
Network two_corner_disks() {
  Network net;
  net.boundary = Boundary::walls;
  net.length = {10.0, 10.0};
  net.material.k_n = 1e3;
  net.material.k_t = 500.0;
  net.material.mu = 0.5;
  net.material.mu_wall = 0.5;
  const double r = 0.5, h = 1.0 / net.material.k_n;  // F_N = K_N h = 1
  net.x = {r - h, 10.0 - r + h};
  net.y = {r - h, r - h};
  net.radius = {r, r};
  net.theta = {0.0, 0.0};
  net.contacts.add(0, wall_bottom, 0, 0, 0.0);
  net.contacts.add(0, wall_left, 0, 0, 0.0);
  net.contacts.add(1, wall_bottom, 0, 0, 0.0);
  net.contacts.add(1, wall_right, 0, 0, 0.0);
  net.constraints.cell_free = {false, false};
  net.constraints.remove_rattlers = false;  // two contacts and a dead load each
  net.loading.dead.assign(6, 0.0);
  rebuild_degrees_of_freedom(net);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const Eigen::VectorXd r0 = residual(net, zero, evaluate_contacts(net, zero));
  for (int i = 0; i < 2; ++i) {
    net.loading.dead[3 * i] = -r0[net.dofs.ux[i]];
    net.loading.dead[3 * i + 1] = -r0[net.dofs.uy[i]];
  }
  return net;
}

// Disk 0 pushed a little further into its corner, and a loop started with its two contacts open
// (the warm statuses of an earlier iterate): its rows carry the push with no dof to balance it.
struct Pushed {
  Network net = two_corner_disks();
  PredictorResult warm;
  Pushed() {
    net.loading.dead[0] -= 0.01;
    net.loading.dead[1] -= 0.01;
    warm.ok = true;
    warm.statuses = {ContactStatus::open, ContactStatus::open, ContactStatus::stick,
                     ContactStatus::stick};
  }
};

TEST(DroppedDisk, TheTwoDisksStartInEquilibriumWithTheirContactsSticking) {
  const Network net = two_corner_disks();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  ASSERT_EQ(states.size(), 4u);
  for (const ContactState& s : states) EXPECT_NEAR(s.f_n, 1.0, 1e-12);
  for (const ContactStatus s : classify_contacts(states)) EXPECT_EQ(s, ContactStatus::stick);
  EXPECT_LT(residual(net, zero, states).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(DroppedDisk, WithoutResolvingTheLoopReportsTheDroppedRows) {
  const Pushed p;
  const PredictorResult r = predict(p.net, SolverOptions{}, nullptr, nullptr, &p.warm, false);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.failure, "dropped rows out of balance");
  EXPECT_TRUE(r.unbalanced_rows);  // so that the step floor retries it resolved
}

// A step's right-hand side R(0) holds the start's own residual (the corrector's leftover, ~1e-10
// of the mean force) as well as the step's load. On dropped rows the solve cannot balance it, and
// it does not shrink with the step: given by the check of the state (start_residual), it is taken
// off, so that a start residual alone never fails a step, however small the step. The same
// residual with no start_residual known still fails; a push of the step itself fails either way.
TEST(DroppedDisk, TheStartsResidualIsNotTheStepsForce) {
  const SolverOptions options;
  const double leftover = 5e-10;  // series A N = 3025 had 5.6e-10 on a dropped disk
  Pushed p;
  p.net.loading.dead[0] += 0.01 - leftover;  // disk 0 off balance by its start residual alone
  p.net.loading.dead[1] += 0.01 - leftover;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p.net.dofs.size);
  const Eigen::VectorXd start = residual(p.net, zero, evaluate_contacts(p.net, zero));
  EXPECT_NEAR(std::abs(start[p.net.dofs.ux[0]]), leftover, 1e-12);

  const PredictorResult unknown = predict(p.net, options, nullptr, nullptr, &p.warm, false);
  EXPECT_EQ(unknown.failure, "dropped rows out of balance");

  p.warm.start_residual = start;
  const PredictorResult known = predict(p.net, options, nullptr, nullptr, &p.warm, false);
  EXPECT_TRUE(known.ok) << known.failure;

  p.net.loading.dead[0] -= 1e-3;  // the step's own push on disk 0's rows
  const PredictorResult pushed = predict(p.net, options, nullptr, nullptr, &p.warm, false);
  EXPECT_EQ(pushed.failure, "dropped rows out of balance");
}

// Resolved, a step's predictor ends consistent with disk 0 let go (its dofs dropped, increment 0);
// the check (a given right-hand side) still refuses the statuses.
TEST(DroppedDisk, ResolvedThePredictorLetsTheDiskGoButTheCheckDoesNot) {
  const Pushed p;
  SolverOptions options;
  options.resolve_unbalanced_rows = true;
  const PredictorResult step = predict(p.net, options, nullptr, nullptr, &p.warm, false);
  ASSERT_TRUE(step.ok) << step.failure;
  EXPECT_EQ(step.statuses[0], ContactStatus::open);
  EXPECT_EQ(step.statuses[1], ContactStatus::open);
  EXPECT_FALSE(step.kept[p.net.dofs.ux[0]]);

  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p.net.dofs.size);
  const Eigen::VectorXd rhs = residual(p.net, zero, evaluate_contacts(p.net, zero));
  const PredictorResult check = predict(p.net, options, nullptr, &rhs, &p.warm, true);
  EXPECT_FALSE(check.ok);
  EXPECT_EQ(check.failure, "dropped rows out of balance");
}

// The corrector of that step moves every disk on the full equilibrium: disk 0 ends pressed
// further into its corner, both contacts closed and carrying the push. By symmetry it does not
// turn; each wall takes the push along its normal through K_N and across it through the other
// wall's K_T: dF_N = 0.01 K_N / (K_N + K_T), |F_T| = 0.01 K_T / (K_N + K_T).
TEST(DroppedDisk, TheCorrectorClosesTheLetGoDisksContacts) {
  Pushed p;
  SolverOptions options;
  options.resolve_unbalanced_rows = true;
  const StepResult s = load_step(p.net, options, nullptr, &p.warm);
  ASSERT_TRUE(s.ok) << s.failure;
  const std::vector<ContactState> states =
      evaluate_contacts(p.net, Eigen::VectorXd::Zero(p.net.dofs.size));
  ASSERT_EQ(states.size(), 4u);
  const double k_n = p.net.material.k_n, k_t = p.net.material.k_t;
  for (int c = 0; c < 2; ++c) {
    EXPECT_NEAR(states[c].f_n, 1.0 + 0.01 * k_n / (k_n + k_t), 1e-6) << c;
    EXPECT_NEAR(std::abs(states[c].f_t), 0.01 * k_t / (k_n + k_t), 1e-6) << c;
  }
  EXPECT_NEAR(std::abs(p.net.theta[0]), 0.0, 1e-12);
  EXPECT_NEAR(states[2].f_n, 1.0, 1e-9);  // disk 1 untouched
}

}  // namespace
}  // namespace granstab::statics
