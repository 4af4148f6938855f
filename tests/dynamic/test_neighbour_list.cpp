// The Verlet list never misses a contact: during a violent compaction (fast affine contraction
// of a light cell, large non-affine motion) and a fast strain-rate shear, the contacts the
// engine reports are exactly the overlapping pairs found by brute force over the cell list.
#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "common/pair_search.hpp"
#include "helpers.hpp"

namespace granstab {
namespace {

void expect_all_contacts_found(const Engine& e) {
  const Configuration c = e.configuration();
  std::set<std::pair<int, int>> reported;
  for (std::size_t k = 0; k < c.contacts.size(); ++k) {
    reported.insert({c.contacts.i[k], c.contacts.j[k]});
  }
  // gap < 0 <=> h > 0
  const PairList overlapping = find_pairs(c.disks.x, c.disks.y, c.disks.radius, c.cell, 0.0);
  std::set<std::pair<int, int>> expected;
  for (std::size_t p = 0; p < overlapping.size(); ++p) {
    expected.insert({overlapping.i[p], overlapping.j[p]});
  }
  ASSERT_EQ(reported, expected) << "step " << e.step_count();
}

TEST(NeighbourList, NoContactMissedUnderAffineContraction) {
  // Equal disks at rest on a square lattice, all gaps 0.2 > skin, in a cell contracted at a
  // prescribed rate: only the affine part moves them, every pair closes at once, and only the
  // contraction term of the rebuild test can have listed them (checked: without it this fails).
  const Material m = Material::from_kappa(1e3, 1.0, 0.3, 0.5);
  Configuration c = testing::empty_periodic(12.0, 12.0, m);
  for (int a = 0; a < 10; ++a) {
    for (int b = 0; b < 10; ++b) c.disks.add(0.6 + 1.2 * a, 0.6 + 1.2 * b, 0.5);
  }
  c.stage.control = {LengthControl::strain_rate, LengthControl::strain_rate};
  c.stage.strain_rate = {0.5, 0.5};
  EngineOptions o;
  o.skin = 0.05;
  Engine e(c, o);
  for (int k = 0; k < 30; ++k) {
    e.run(10);
    expect_all_contacts_found(e);
  }
  EXPECT_EQ(e.contact_count(), 200u);  // every lattice bond closed
}

TEST(NeighbourList, NoContactMissedWhileTheCellDeforms) {
  Configuration c = testing::random_gas(300, 0.2, Material::from_kappa(1e3, 1.0, 0.3, 0.5), 8);
  c.stage.control = {LengthControl::stress, LengthControl::stress};
  c.stage.sigma_ext = {1.0, 2.0};
  for (double& m : c.cell.mass) m *= 0.01;  // a light cell: the fastest contraction
  EngineOptions o;
  o.skin = 0.05;
  Engine e(c, o);
  std::size_t max_contacts = 0;
  for (int k = 0; k < 150; ++k) {
    e.run(40);
    expect_all_contacts_found(e);
    max_contacts = std::max(max_contacts, e.contact_count());
  }
  EXPECT_GT(max_contacts, 300u);           // the sample did become dense
  EXPECT_GT(e.neighbour_rebuilds(), 20u);  // and the list was rebuilt along the way
  // Then shear it fast: axis 2 compressed at a strain rate of 1e-2, axis 1 under stress.
  e.set_reference_lengths_to_current();
  e.set_strain_rate_control(1, 1e-2);
  for (int k = 0; k < 50; ++k) {
    e.run(40);
    expect_all_contacts_found(e);
  }
}

}  // namespace
}  // namespace granstab
