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

// A step that moves a disk by more than its radius has followed a floppy mode (series A, N = 3025:
// three disks slid 4.3e6 along a frictionless wall and became rattlers there): escaped_disk names
// the first such disk, its motion counted from where the cell's affine motion takes it.
TEST(VanishingContacts, EscapedDiskIsTheFirstMovedByMoreThanItsRadius) {
  Network before = network_from_configuration(read_configuration(sample));
  Network after = before;
  EXPECT_EQ(escaped_disk(before, after), -1);
  // The cell shrinks by 1 % in x and grows by 1 % in y, every disk with it: no escape.
  after.length = {0.99 * before.length[0], 1.01 * before.length[1]};
  for (std::size_t i = 0; i < after.n_disks(); ++i) {
    after.x[i] = 0.99 * before.x[i];
    after.y[i] = 1.01 * before.y[i];
  }
  EXPECT_EQ(escaped_disk(before, after), -1);
  const int a = 3, b = 7;
  const double rb = before.radius[b], ra = before.radius[a];
  after.x[b] += 0.99 * rb / std::sqrt(2.0);  // just within the radius, along a diagonal
  after.y[b] += 0.99 * rb / std::sqrt(2.0);
  EXPECT_EQ(escaped_disk(before, after), -1);
  after.y[b] += 0.03 * rb;
  EXPECT_EQ(escaped_disk(before, after), b);
  after.x[a] -= 1.5 * ra;
  EXPECT_EQ(escaped_disk(before, after), a);  // the first in disk order
}

// A rattler made inside a step can be closed on by the disks around it in the rounds after
// (series A, N = 3025). Overlapped twice it would carry unbalanced forces at the next preparation:
// clear_rattler_overlaps moves it by the shortest displacement that opens them. A rattler whose
// contacts surround it (jammed) stays.
TEST(VanishingContacts, ClearRattlerOverlapsMovesARattlerOffTwoContacts) {
  Network net = network_from_configuration(read_configuration(sample));
  prepare(net, SolverOptions{});
  const Network start = net;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  // A disk whose overlaps leave no half-plane free (jammed), two of them (c1, c2) 30 to 120
  // degrees apart.
  int disk = -1, c1 = -1, c2 = -1;
  for (std::size_t i = 0; i < net.n_disks() && disk < 0; ++i) {
    if (net.dofs.ux[i] < 0) continue;
    std::vector<std::pair<double, int>> around;  // direction towards the other body, contact
    for (std::size_t c = 0; c < states.size(); ++c) {
      const int a = net.contacts.i[c], b = net.contacts.j[c];
      if ((a != static_cast<int>(i) && b != static_cast<int>(i)) || !(states[c].frame.h > 0.0))
        continue;
      const double s = a == static_cast<int>(i) ? 1.0 : -1.0;
      around.emplace_back(std::atan2(s * states[c].frame.ny, s * states[c].frame.nx), c);
    }
    if (around.size() < 3) continue;
    std::sort(around.begin(), around.end());
    double gap = 2.0 * M_PI - (around.back().first - around.front().first);
    for (std::size_t k = 1; k < around.size(); ++k)
      gap = std::max(gap, around[k].first - around[k - 1].first);
    if (gap > 0.9 * M_PI) continue;
    for (std::size_t k = 1; k < around.size() && c1 < 0; ++k) {
      const double apart = around[k].first - around[k - 1].first;
      if (apart > M_PI / 6 && apart < 2 * M_PI / 3) {
        disk = static_cast<int>(i);
        c1 = around[k - 1].second;
        c2 = around[k].second;
      }
    }
  }
  ASSERT_GE(disk, 0);
  Eigen::VectorXd dq = zero;
  ASSERT_TRUE(make_rattlers(net, {disk}, dq));
  const Network jammed = net;
  std::vector<int> jammed_disks;
  EXPECT_TRUE(
      clear_rattler_overlaps(net, {disk}, dq, evaluate_contacts(net, dq), jammed_disks).empty());
  EXPECT_EQ(jammed_disks, std::vector<int>{disk});
  EXPECT_EQ(net.x[disk], jammed.x[disk]);
  EXPECT_EQ(net.y[disk], jammed.y[disk]);
  // The same disk shrunk to 0.7 r and put where it overlaps the partners of c1 and c2 only, by
  // 1e-6 and 2e-6, with those two its only listed contacts.
  net = start;
  const std::array<int, 2> partner = {
      net.contacts.i[c1] == disk ? net.contacts.j[c1] : net.contacts.i[c1],
      net.contacts.i[c2] == disk ? net.contacts.j[c2] : net.contacts.i[c2]};
  const auto offset = [&net](int from, int to) {  // minimum image
    double dx = net.x[to] - net.x[from], dy = net.y[to] - net.y[from];
    dx -= net.length[0] * std::round(dx / net.length[0]);
    dy -= net.length[1] * std::round(dy / net.length[1]);
    return std::array<double, 2>{dx, dy};
  };
  net.radius[disk] *= 0.7;
  {
    const std::array<double, 2> p = offset(disk, partner[0]), q = offset(disk, partner[1]);
    const double rp = net.radius[disk] + net.radius[partner[0]] - 1e-6;
    const double rq = net.radius[disk] + net.radius[partner[1]] - 2e-6;
    const double dx = q[0] - p[0], dy = q[1] - p[1], d = std::hypot(dx, dy);
    const double along = (rp * rp - rq * rq + d * d) / (2.0 * d);
    const double half = std::sqrt(rp * rp - along * along);
    // Of the two places, the one nearer the old centre (inside the cage).
    const double fx = p[0] + along * dx / d, fy = p[1] + along * dy / d;
    const double ax = fx - half * dy / d, ay = fy + half * dx / d;
    const double bx = fx + half * dy / d, by = fy - half * dx / d;
    const bool first = std::hypot(ax, ay) < std::hypot(bx, by);
    net.x[disk] += first ? ax : bx;
    net.y[disk] += first ? ay : by;
  }
  const auto overlapping = [&net, &offset](int d) {
    std::vector<double> h;
    for (std::size_t p = 0; p < net.n_disks(); ++p) {
      if (static_cast<int>(p) == d) continue;
      const std::array<double, 2> v = offset(d, static_cast<int>(p));
      const double overlap = net.radius[d] + net.radius[p] - std::hypot(v[0], v[1]);
      if (overlap > 0.0) h.push_back(overlap);
    }
    return h;
  };
  ASSERT_EQ(overlapping(disk).size(), 2u);
  Contacts two;
  const Contacts& all = start.contacts;
  for (std::size_t c = 0; c < all.size(); ++c) {
    const bool its = all.i[c] == disk || all.j[c] == disk;
    if (!its || static_cast<int>(c) == c1 || static_cast<int>(c) == c2)
      two.add(all.i[c], all.j[c], all.k1[c], all.k2[c], all.delta_t[c], all.status[c]);
  }
  net.contacts = two;
  rebuild_degrees_of_freedom(net);  // no polish: it would move the disk off c1 and c2
  dq = Eigen::VectorXd::Zero(net.dofs.size);
  if (!net.dofs.is_rattler(disk)) {
    ASSERT_TRUE(make_rattlers(net, {disk}, dq));
  }
  const std::vector<ContactState> before = evaluate_contacts(net, dq);
  std::vector<int> touching;
  for (std::size_t c = 0; c < before.size(); ++c)
    if (net.contacts.i[c] == disk || net.contacts.j[c] == disk) {
      touching.push_back(static_cast<int>(c));
      ASSERT_GT(before[c].frame.h, 0.0);
    }
  ASSERT_EQ(touching.size(), 2u);
  const double x0 = net.x[disk], y0 = net.y[disk];
  jammed_disks.clear();
  EXPECT_EQ(clear_rattler_overlaps(net, {disk}, dq, before, jammed_disks), std::vector<int>{disk});
  EXPECT_TRUE(jammed_disks.empty());
  const std::vector<ContactState> after = evaluate_contacts(net, dq);
  bool binding = false;
  for (const int c : touching) {
    // Opened to a gap of 0.01 h or more; the nearest place leaves at least one exactly so.
    const double h = before[c].frame.h;
    EXPECT_LE(after[c].frame.h, -0.01 * h * (1.0 - 1e-6)) << c;
    binding = binding || std::abs(after[c].frame.h + 0.01 * h) < 1e-6 * h;
  }
  EXPECT_TRUE(binding);
  EXPECT_TRUE(overlapping(disk).empty());
  EXPECT_LT(std::hypot(net.x[disk] - x0, net.y[disk] - y0), 0.1 * net.radius[disk]);
}

}  // namespace
}  // namespace granstab::statics
