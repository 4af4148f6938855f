// A rattler has no force balance (SPEC §2: it carries no force), so a listed contact that
// overlaps it must carry none either. Before, such a contact made the rattler an obstacle moved
// affinely with the cell that pushed its neighbour with an unbalanced force, and whether the
// grazing contact of a new rattler stayed listed (h = 0 to round-off after the step) decided
// between two equilibria of periodic-n100 at mu = 0.5 (issue #5, docs/static.md "Round-off-robust
// decisions": q1 = 0.791 or 0.824 depending on the ordering).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "common/io/configuration_file.hpp"
#include "static/backbone.hpp"
#include "static/kinematics.hpp"
#include "static/load_step.hpp"

namespace granstab::statics {
namespace {

TEST(RattlerContacts, AnOverlappingListedContactOfARattlerCarriesNoForce) {
  const Configuration config = read_configuration(std::filesystem::path(GRANSTAB_SAMPLES_DIR) /
                                                  "periodic-n100-k1e4.granstab");
  Network net = network_from_configuration(config);
  net.constraints.remove_rattlers = true;
  rebuild_degrees_of_freedom(net);
  // A rattler and its nearest active disk (minimum image).
  int rattler = -1, partner = -1;
  double nearest = INFINITY, lx = 0.0, ly = 0.0;
  for (std::size_t r = 0; r < net.n_disks() && rattler < 0; ++r) {
    if (net.dofs.active(r)) continue;
    for (std::size_t a = 0; a < net.n_disks(); ++a) {
      if (!net.dofs.active(a)) continue;
      double dx = net.x[r] - net.x[a], dy = net.y[r] - net.y[a];
      dx -= net.length[0] * std::round(dx / net.length[0]);
      dy -= net.length[1] * std::round(dy / net.length[1]);
      if (std::hypot(dx, dy) < nearest) {
        nearest = std::hypot(dx, dy);
        rattler = static_cast<int>(r);
        partner = static_cast<int>(a);
        lx = dx;
        ly = dy;
      }
    }
  }
  ASSERT_GE(rattler, 0) << "the sample has rattlers (94 of its 100 disks carry force)";
  // Put the rattler against its neighbour with an overlap of 1e-4 a and list the contact: it
  // keeps a single force-carrying contact, so it stays a rattler.
  const double d = net.radius[rattler] + net.radius[partner] - 1e-4;
  net.x[rattler] = net.x[partner] + d * lx / nearest;
  net.y[rattler] = net.y[partner] + d * ly / nearest;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const Eigen::VectorXd before = residual(net, zero, evaluate_contacts(net, zero));
  const std::size_t c = net.contacts.add(partner, rattler, 0, 0);
  rebuild_degrees_of_freedom(net);
  ASSERT_FALSE(net.dofs.active(rattler));
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  EXPECT_GT(states[c].frame.h, 0.9e-4);
  EXPECT_EQ(states[c].f_n, 0.0);  // before: 0.97 P a on the partner, balanced by nothing
  EXPECT_EQ(states[c].f_t, 0.0);
  EXPECT_EQ((residual(net, zero, states) - before).cwiseAbs().maxCoeff(), 0.0);
  // It stays listed while it overlaps (the rattler rejoins once two of its contacts carry load).
  advance(net, zero, states);
  bool listed = false;
  for (std::size_t k = 0; k < net.contacts.size(); ++k)
    listed = listed || (net.contacts.i[k] == partner && net.contacts.j[k] == rattler);
  EXPECT_TRUE(listed);
}

}  // namespace
}  // namespace granstab::statics
