// New contacts during a step (STATIC.md §S3.2): overlaps of active disks not in the list, found
// through periodic images, in small cells (all pairs) and large ones (common cell list).
#include <gtest/gtest.h>

#include "static/closing_contacts.hpp"
#include "static/load_step.hpp"

namespace granstab::statics {
namespace {

// Two disks of radius 1/2 on the line y = 1, separated across the periodic boundary by a gap
// of 0.01 (disk 1 sits at the right end of a cell of length L, disk 0 at its left end).
Network pair_across_boundary(double length) {
  Network net;
  net.boundary = Boundary::periodic;
  net.length = {length, length};
  net.x = {0.5, length - 0.51};
  net.y = {1.0, 1.0};
  net.radius = {0.5, 0.5};
  net.theta = {0.0, 0.0};
  DofOptions o;
  o.active = {1, 1};
  o.pinned_translation = 0;
  o.cell = {false, false};
  net.dofs = build_dof_map(o);
  return net;
}

void expect_closes_through_the_image(double length) {
  const Network net = pair_across_boundary(length);
  Eigen::VectorXd dq = Eigen::VectorXd::Zero(net.dofs.size);
  EXPECT_TRUE(closing_contacts(net, dq).empty());
  dq[net.dofs.ux[1]] = 0.02;  // disk 1 moves right by 0.02 and overlaps disk 0's image by 0.01
  const std::vector<NewContact> found = closing_contacts(net, dq);
  ASSERT_EQ(found.size(), 1u) << length;
  const NewContact& c = found[0];
  // l = x_j + k1 L - x_i must be the overlapping branch, of length 0.99.
  const double x[2] = {0.5, length - 0.51 + 0.02};
  EXPECT_NEAR(std::abs(x[c.j] + c.k1 * length - x[c.i]), 0.99, 1e-12) << length;
  EXPECT_EQ(c.k2, 0);
}

TEST(ClosingContacts, FoundThroughThePeriodicImage) {
  expect_closes_through_the_image(3.0);   // below the cell-list size limit: all pairs
  expect_closes_through_the_image(20.0);  // cell list of common/pair_search.hpp
}

TEST(ClosingContacts, KnownContactsAreNotRepeated) {
  Network net = pair_across_boundary(20.0);
  net.contacts.add(1, 0, 1, 0);  // the same pair, listed from disk 1
  Eigen::VectorXd dq = Eigen::VectorXd::Zero(net.dofs.size);
  dq[net.dofs.ux[1]] = 0.02;
  EXPECT_TRUE(closing_contacts(net, dq).empty());
}

}  // namespace
}  // namespace granstab::statics
