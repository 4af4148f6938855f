// A rattler that the cage closes on must be pushed along (xcheck's finding on periodic-n100 at
// mu = 0.5: active disks overlapped rattlers by up to 1.4e-3 a, the static state was no
// equilibrium for the dynamic module). With SolverOptions::push_rattlers, closing_contacts finds
// the pair and the load step gives the rattler dofs in the same step (activate_disks). Without
// the option, a rattler whose *listed* contacts the cage closes is still cleared or given dofs in
// the step (caught_rattlers), so that the state accepted is an equilibrium.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "common/io/configuration_file.hpp"
#include "static/backbone.hpp"
#include "static/kinematics.hpp"
#include "static/load_step.hpp"
#include "static/q1.hpp"

namespace granstab::statics {
namespace {

// Largest overlap of two disks that is not in the contact list (minimum image).
double largest_unlisted_overlap(const Network& net) {
  double worst = 0.0;
  const std::size_t n = net.n_disks();
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b) {
      double dx = net.x[b] - net.x[a], dy = net.y[b] - net.y[a];
      dx -= net.length[0] * std::round(dx / net.length[0]);
      dy -= net.length[1] * std::round(dy / net.length[1]);
      const double h = net.radius[a] + net.radius[b] - std::hypot(dx, dy);
      if (h <= 0.0) continue;
      bool listed = false;
      for (std::size_t c = 0; c < net.contacts.size() && !listed; ++c) {
        const int i = net.contacts.i[c], j = net.contacts.j[c];
        listed = (i == static_cast<int>(a) && j == static_cast<int>(b)) ||
                 (i == static_cast<int>(b) && j == static_cast<int>(a));
      }
      if (!listed) worst = std::max(worst, h);
    }
  return worst;
}

TEST(CagedRattler, TheCageClosingOnARattlerPushesIt) {
  // The 16-disk triangular lattice (kappa = 1e3, overlaps 5.8e-4 at P = 1) with disk 5 shrunk
  // by 1e-3: a rattler in a cage that closes on it as sigma_2 grows.
  Configuration config = read_configuration(std::filesystem::path(GRANSTAB_SAMPLES_DIR) /
                                            "tiny-triangular-periodic.granstab");
  const int rattler = 5;
  config.disks.radius[rattler] *= 1.0 - 2e-3;
  Contacts kept;
  for (std::size_t c = 0; c < config.contacts.size(); ++c)
    if (config.contacts.i[c] != rattler && config.contacts.j[c] != rattler)
      kept.add(config.contacts.i[c], config.contacts.j[c], config.contacts.k1[c],
               config.contacts.k2[c], config.contacts.delta_t[c], config.contacts.status[c]);
  config.contacts = kept;
  Q1Options o;
  o.dq = 0.25;
  o.hill_every = 0;
  o.load_stop = 6.0;
  o.solver.push_rattlers = true;
  const StabilityResult r = find_q1(config, o);
  const Network& net = r.network_at_q1;
  const std::vector<ContactState> states =
      evaluate_contacts(net, Eigen::VectorXd::Zero(net.dofs.size));
  double rattler_force = 0.0;
  for (std::size_t c = 0; c < states.size(); ++c)
    if (net.contacts.i[c] == rattler || net.contacts.j[c] == rattler)
      rattler_force = std::max(rattler_force, states[c].f_n);
  const double unlisted = largest_unlisted_overlap(net);
  std::printf("q = %.3f (%s), largest force on the rattler %.4g, largest unlisted overlap %.3g\n",
              r.q1, criterion_name(r.criterion), rattler_force, unlisted);
  EXPECT_EQ(r.criterion, Criterion::none) << r.detail;
  EXPECT_GT(rattler_force, 0.1);  // the cage closed on it
  EXPECT_EQ(unlisted, 0.0);
  // The default (off) leaves the cage overlapping the rattler (4.4e-3 a at q = 6).
  o.solver.push_rattlers = false;
  const StabilityResult off = find_q1(config, o);
  EXPECT_GT(largest_unlisted_overlap(off.network_at_q1), 1e-3);
}

TEST(CagedRattler, AStepThatClosesARattlersListedContactsEndsInAnEquilibrium) {
  // The 16-disk lattice at equilibrium; then disk 5 shrinks by 2e-3 of its radius, so that its
  // six listed contacts gap by ~4e-4 and it is a rattler, and the load step to q = 1 collapses
  // the cage onto it. Its listed contacts then overlap again: at the next preparation it would
  // rejoin with contacts out of balance by K_N times those overlaps (series A, N = 3025, seed 1:
  // the fixed steps stopped at q = 0.7215 after such a state). The step must end in a state that
  // is an equilibrium once the dofs are rebuilt.
  const Configuration config = read_configuration(std::filesystem::path(GRANSTAB_SAMPLES_DIR) /
                                                  "tiny-triangular-periodic.granstab");
  Network net = network_from_configuration(config);
  net.constraints.cell_free = {true, true};
  net.constraints.remove_rattlers = true;
  const SolverOptions options;
  prepare(net, options);
  const int rattler = 5;
  net.radius[rattler] *= 1.0 - 2e-3;
  rebuild_degrees_of_freedom(net);
  ASSERT_TRUE(net.dofs.is_rattler(rattler));
  net.loading.sigma = {1.0, 2.0};
  const StepResult step = load_step(net, options);
  ASSERT_TRUE(step.ok) << step.failure;
  int overlapping = 0;  // the listed contacts of the rattler that the cage closed
  for (std::size_t c = 0; c < net.contacts.size(); ++c)
    if (net.contacts.i[c] == rattler || net.contacts.j[c] == rattler) ++overlapping;
  rebuild_degrees_of_freedom(net);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  const double r = relative_residual(net, residual(net, zero, states), residual_scale(net, states));
  std::printf("disk %d: rattler %d, %d listed contacts, relative residual %.3g\n", rattler,
              static_cast<int>(net.dofs.is_rattler(rattler)), overlapping, r);
  EXPECT_GE(overlapping, 2);  // the case the test is about: the cage closed on two or more
  EXPECT_LT(r, options.tolerance);
}

}  // namespace
}  // namespace granstab::statics
