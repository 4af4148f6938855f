// The Verlet list never misses a contact: during a violent compaction (fast affine contraction
// of a light cell, large non-affine motion) and a fast strain-rate shear, the contacts the
// engine reports are exactly the overlapping pairs found by brute force over the cell list.
#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "common/pair_search.hpp"
#include "dynamic/neighbour_list.hpp"
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

TEST(NeighbourList, RebuildsOfAGrowingListStayInTheFirstBuildsRoom) {
  // A rebuild fills one of two sets of per-pair arrays and reads the other (the old list, whose
  // state it carries over); the next rebuild swaps them. The first build leaves room in both
  // (keep_room), so that the rebuilds inside a run, the list a few % longer each time, allocate
  // nothing: no fresh pages in the run loop. (Without that room the second rebuild here moves
  // to new storage: checked by hand.)
  Configuration c = testing::random_gas(400, 0.5, Material::from_kappa(1e3, 1.0, 0.3, 0.7), 5);
  const std::size_t n = c.disks.size();
  dynamic::DiskArrays disks;
  for (auto* v : {&disks.x, &disks.y, &disks.radius, &disks.mass}) v->assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    disks.x[i] = c.disks.x[i];
    disks.y[i] = c.disks.y[i];
    disks.radius[i] = c.disks.radius[i];
    disks.mass[i] = c.disks.mass[i];
  }
  dynamic::CellState cell;
  cell.length = c.cell.length;
  dynamic::PairArrays pairs;
  dynamic::NeighbourList list(0.5);
  std::vector<std::size_t> sizes;
  std::vector<std::vector<const void*>> storage;
  for (int build = 0; build < 4; ++build) {
    list.rebuild(disks, cell, pairs, c.material);
    sizes.push_back(pairs.size());
    storage.push_back({pairs.i.data(), pairs.j.data(), pairs.delta_t.data(), pairs.f_n.data(),
                       pairs.viscous_x.data(), pairs.viscous_y.data(), pairs.alpha.data(),
                       pairs.nx.data(), pairs.lx.data(), pairs.active.data()});
    // An affine compression of 1 %: more pairs within reach at the next build.
    for (std::size_t i = 0; i < n; ++i) {
      disks.x[i] *= 0.99;
      disks.y[i] *= 0.99;
    }
    for (double& l : cell.length) l *= 0.99;
  }
  for (int build = 1; build < 4; ++build) {
    ASSERT_GT(sizes[build], sizes[build - 1]);
    ASSERT_LT(sizes[build], sizes[0] + sizes[0] / 8);  // within the room
  }
  EXPECT_EQ(storage[2], storage[0]);
  EXPECT_EQ(storage[3], storage[1]);
}

}  // namespace
}  // namespace granstab
