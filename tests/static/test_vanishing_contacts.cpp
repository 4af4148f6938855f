// SPEC §4: a disk whose force-carrying contacts open together inside a step (a two-contact disk
// whose forces tend to 0) becomes a rattler; it must not make the network look unstable.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>

#include "common/io/configuration_file.hpp"
#include "static/backbone.hpp"
#include "static/linear_solvers.hpp"
#include "static/load_step.hpp"
#include "static/q1.hpp"

namespace granstab::statics {
namespace {

const std::filesystem::path sample =
    std::filesystem::path(GRANSTAB_SAMPLES_DIR) / "periodic-n100-k1e4.granstab";

TEST(VanishingContacts, DiskWithAllContactsOpenLosesItsDofs) {
  Network net = network_from_configuration(read_configuration(sample));
  prepare(net, SolverOptions{});
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  std::vector<ContactStatus> statuses = classify_contacts(states);
  const std::vector<char> before = kept_dofs(net, states, statuses);
  // Open every contact of one force-carrying disk (not the translation-pinned one).
  int disk = -1;
  for (std::size_t i = 0; i < net.n_disks() && disk < 0; ++i)
    if (net.dofs.ux[i] >= 0 && net.dofs.theta[i] >= 0 && before[net.dofs.theta[i]])
      disk = static_cast<int>(i);
  ASSERT_GE(disk, 0);
  for (std::size_t c = 0; c < states.size(); ++c)
    if (net.contacts.i[c] == disk || net.contacts.j[c] == disk) statuses[c] = ContactStatus::open;
  const std::vector<char> after = kept_dofs(net, states, statuses);
  EXPECT_FALSE(after[net.dofs.ux[disk]]);
  EXPECT_FALSE(after[net.dofs.uy[disk]]);
  EXPECT_FALSE(after[net.dofs.theta[disk]]);
  int dropped = 0;
  for (std::size_t d = 0; d < after.size(); ++d) dropped += before[d] && !after[d];
  EXPECT_EQ(dropped, 3);  // the disk only: its neighbours keep their other contacts
  LuFactor lu;
  EXPECT_TRUE(lu.factorize(reduce(assemble_tangent(net, states, statuses), make_reduction(after))));
}

// On the shipped sample at mu = 0.5, disk 38 carries two contacts whose forces fall to ~1e-9 near
// q = 0.289; the increment opens both. Before the rattler transition was handled, every step from
// there was "predictor: singular" down to the floor (q1 = 0.28909, criterion existence, the mode
// a lone translation of that disk); the stepping must go past it.
TEST(VanishingContacts, NewRattlerInsideAStepIsNotAnInstability) {
  Configuration c = read_configuration(sample);
  c.material.mu = 0.5;
  c.stage.reference_length = c.cell.length;
  Q1Options o;
  o.dq = 1e-2;
  o.hill_every = 0;
  o.load_stop = 0.35;
  const StabilityResult r = find_q1(c, o);
  EXPECT_EQ(r.criterion, Criterion::none) << r.q1 << " " << r.detail;
  EXPECT_GE(r.q1, 0.35);
}

// The corrector's side (load_step.cpp): a disk left with one closed contact becomes a rattler
// (make_rattlers): its dofs go, the others keep their values, it stays where dq had moved it, its
// contacts carry no force, and the translation-pinned disk is refused (removing it would change
// the gauge of every u).
TEST(VanishingContacts, MakeRattlersDropsTheDisksAndTheirForces) {
  Network net = network_from_configuration(read_configuration(sample));
  prepare(net, SolverOptions{});
  const Network start = net;
  const DofMap before = net.dofs;
  int disk = -1, pinned = -1;
  for (std::size_t i = 0; i < net.n_disks(); ++i) {
    if (before.ux[i] < 0 && before.theta[i] >= 0) pinned = static_cast<int>(i);
    if (disk < 0 && before.ux[i] >= 0) disk = static_cast<int>(i);
  }
  ASSERT_GE(disk, 0);
  ASSERT_GE(pinned, 0);
  Eigen::VectorXd dq = 1e-4 * Eigen::VectorXd::LinSpaced(before.size, 1.0, double(before.size));
  const std::array<double, 2> e = cell_extension(net, dq);
  Eigen::VectorXd kept = dq;
  EXPECT_FALSE(make_rattlers(net, {pinned}, kept));
  EXPECT_EQ(net.dofs.size, before.size);
  ASSERT_TRUE(make_rattlers(net, {disk}, dq));
  EXPECT_EQ(net.dofs.size, before.size - 3);
  EXPECT_TRUE(net.dofs.is_rattler(disk));
  EXPECT_LT(net.dofs.ux[disk], 0);
  EXPECT_LT(net.dofs.theta[disk], 0);
  // Moved affinely from here on, it ends where the step's dq would have put it.
  EXPECT_DOUBLE_EQ((1.0 + e[0]) * net.x[disk],
                   (1.0 + e[0]) * start.x[disk] + kept[before.ux[disk]]);
  EXPECT_DOUBLE_EQ((1.0 + e[1]) * net.y[disk],
                   (1.0 + e[1]) * start.y[disk] + kept[before.uy[disk]]);
  EXPECT_DOUBLE_EQ(net.theta[disk], start.theta[disk] + kept[before.theta[disk]]);
  for (std::size_t i = 0; i < net.n_disks(); ++i) {
    if (static_cast<int>(i) == disk) continue;
    EXPECT_EQ(net.x[i], start.x[i]) << i;
    if (before.uy[i] >= 0) {
      EXPECT_EQ(dq[net.dofs.uy[i]], kept[before.uy[i]]) << i;
    }
  }
  const std::vector<ContactState> states =
      evaluate_contacts(net, Eigen::VectorXd::Zero(net.dofs.size));
  int touching = 0;
  for (std::size_t c = 0; c < states.size(); ++c)
    if (net.contacts.i[c] == disk || net.contacts.j[c] == disk) {
      ++touching;
      EXPECT_EQ(states[c].f_n, 0.0);
      EXPECT_EQ(states[c].f_t, 0.0);
    }
  EXPECT_GE(touching, 2);
}

// lone_contacts counts the closed contacts of each disk with dofs: with all but one of a disk's
// contacts open, that one is its lone contact (a partner is named only if left with one too).
// step_off_lone_contacts then moves the disk off it.
TEST(VanishingContacts, LoneContactsNameTheLastClosedContactOfADisk) {
  Network net = network_from_configuration(read_configuration(sample));
  prepare(net, SolverOptions{});
  const std::vector<ContactState> states =
      evaluate_contacts(net, Eigen::VectorXd::Zero(net.dofs.size));
  std::vector<char> closed(states.size());
  for (std::size_t c = 0; c < states.size(); ++c) closed[c] = states[c].f_n > 0.0;
  for (const int c : lone_contacts(net, closed)) EXPECT_EQ(c, -1);  // prepared: >= 2 each
  int disk = -1, keep = -1;
  for (std::size_t c = 0; c < states.size() && disk < 0; ++c)
    if (closed[c] && net.dofs.ux[net.contacts.i[c]] >= 0) {
      disk = net.contacts.i[c];
      keep = static_cast<int>(c);
    }
  ASSERT_GE(disk, 0);
  for (std::size_t c = 0; c < states.size(); ++c)
    if (static_cast<int>(c) != keep && (net.contacts.i[c] == disk || net.contacts.j[c] == disk))
      closed[c] = 0;
  const std::vector<int> lone = lone_contacts(net, closed);
  for (std::size_t i = 0; i < lone.size(); ++i) {
    if (static_cast<int>(i) == disk) {
      EXPECT_EQ(lone[i], keep);
    } else if (lone[i] >= 0) {
      // A partner of the disk can be left with one too (then it is named), never another disk.
      const int c = lone[i];
      EXPECT_TRUE(net.contacts.i[c] == disk || net.contacts.j[c] == disk) << i;
    }
  }
  // Stepping off: the disk moves along the contact's normal by 1.01 h, which opens it.
  const double h = states[keep].frame.h;
  std::vector<int> only(lone.size(), -1);
  only[disk] = keep;
  Eigen::VectorXd dq = Eigen::VectorXd::Zero(net.dofs.size);
  EXPECT_EQ(step_off_lone_contacts(net, only, states, dq), std::vector<int>{disk});
  EXPECT_NEAR(std::hypot(dq[net.dofs.ux[disk]], dq[net.dofs.uy[disk]]), 1.01 * h, 1e-15);
  const double after = evaluate_contact(net, keep, dq).frame.h;
  EXPECT_LT(after, 0.0);
  EXPECT_NEAR(after, -0.01 * h, 1e-3 * h);  // to first order in h / d
}

}  // namespace
}  // namespace granstab::statics
