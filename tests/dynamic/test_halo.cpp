// The halo of a team's parts (dynamic/halo.hpp): each part's ghosts are exactly the other parts'
// disks its crossing pairs and mirrors read, the passes' indices point at them, and the copies
// keep them equal to their disks, bit for bit. (The engine-level check, one and two threads
// giving the same bits, is in test_determinism.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <set>
#include <vector>

#include "dynamic/halo.hpp"
#include "dynamic/neighbour_list.hpp"
#include "dynamic/parts.hpp"
#include "helpers.hpp"

namespace granstab::dynamic {
namespace {

// 400 disks of a gas (7 blocks of 64) and their Verlet list.
struct Sample {
  DiskArrays disks;
  PairArrays pairs;
  Sample() {
    const Configuration c =
        testing::random_gas(400, 0.5, Material::from_kappa(1e3, 1.0, 0.3, 0.7), 5);
    const std::size_t n = c.disks.size();
    for (auto* v : {&disks.x, &disks.y, &disks.radius, &disks.mass, &disks.vx, &disks.vy,
                    &disks.omega, &disks.vpx, &disks.vpy})
      v->assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      disks.x[i] = c.disks.x[i];
      disks.y[i] = c.disks.y[i];
      disks.radius[i] = c.disks.radius[i];
      disks.mass[i] = c.disks.mass[i];
      disks.vx[i] = 0.1 * static_cast<double>(i);
      disks.vy[i] = -0.2 * static_cast<double>(i);
      disks.omega[i] = 0.3 * static_cast<double>(i);
      disks.vpx[i] = 0.4 * static_cast<double>(i);
      disks.vpy[i] = 0.5 * static_cast<double>(i);
    }
    CellState cell;
    cell.length = c.cell.length;
    NeighbourList list(0.5);
    list.rebuild(disks, cell, pairs, c.material);
  }
};

int part_of(const PairArrays& pairs, int disk) {
  const int b = disk / block_size;
  int part = 0;
  while (pairs.part_block[part + 1] <= b) ++part;
  return part;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Every ghosted array holds its disk's value at every ghost.
void expect_ghosts_equal(const DiskArrays& d, const Halo& h) {
  const std::size_t n = d.size();
  for (const auto* v : {&d.x, &d.y, &d.radius, &d.vx, &d.vy, &d.omega, &d.vpx, &d.vpy}) {
    ASSERT_EQ(v->size(), n + h.size());
    for (std::size_t g = 0; g < h.size(); ++g)
      EXPECT_TRUE(same_bits((*v)[n + g], (*v)[h.ghost_disk[g]])) << "ghost " << g;
  }
}

TEST(Halo, EachPartsGhostsAreTheDisksOfOtherPartsItReads) {
  Sample s;
  const std::size_t n = s.disks.size();
  plan_parts(s.disks, s.pairs, {0, 2, 5, 7});  // three parts
  const PairArrays& pairs = s.pairs;
  const Halo& h = pairs.halo;
  const int team = 3;
  ASSERT_EQ(h.ghost_start.size(), static_cast<std::size_t>(team + 1));
  std::vector<std::set<int>> read(team);  // what each part's passes read of the others
  int crossing = 0;
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const int i = pairs.i[p], j = pairs.j[p];
    if (part_of(pairs, i) == part_of(pairs, j)) {
      EXPECT_EQ(pairs.j_slot[p], j);
      continue;
    }
    ++crossing;
    const int part = part_of(pairs, i);
    read[part].insert(j);
    read[part_of(pairs, j)].insert(i);  // its mirror's i
    const int g = pairs.j_slot[p] - static_cast<int>(n);
    ASSERT_GE(g, h.ghost_start[part]);
    ASSERT_LT(g, h.ghost_start[part + 1]);
    EXPECT_EQ(h.ghost_disk[g], j);
  }
  ASSERT_GT(crossing, 20);
  const MirrorPairs& m = pairs.mirrors;
  for (int part = 0; part < team; ++part) {
    const std::vector<int> ghosts(h.ghost_disk.begin() + h.ghost_start[part],
                                  h.ghost_disk.begin() + h.ghost_start[part + 1]);
    EXPECT_EQ(ghosts, std::vector<int>(read[part].begin(), read[part].end())) << "part " << part;
    for (int q = m.part_start[part]; q < m.part_start[part + 1]; ++q) {
      const int g = m.i[q] - static_cast<int>(n);
      ASSERT_GE(g, h.ghost_start[part]);
      ASSERT_LT(g, h.ghost_start[part + 1]);
      EXPECT_EQ(part_of(pairs, m.j[q]), part);
      EXPECT_NE(part_of(pairs, h.ghost_disk[g]), part);
    }
  }
  // Each ghost is sent by the part that owns its disk, once.
  std::vector<int> sent_count(h.size(), 0);
  for (int part = 0; part < team; ++part) {
    for (int k = h.sent_start[part]; k < h.sent_start[part + 1]; ++k) {
      ++sent_count[h.sent[k]];
      EXPECT_EQ(part_of(pairs, h.ghost_disk[h.sent[k]]), part);
    }
  }
  EXPECT_TRUE(std::all_of(sent_count.begin(), sent_count.end(), [](int c) { return c == 1; }));
  expect_ghosts_equal(s.disks, h);
}

TEST(Halo, PackedAndCopiedGhostsFollowTheirDisks) {
  Sample s;
  plan_parts(s.disks, s.pairs, {0, 3, 7});
  DiskArrays& d = s.disks;
  Halo& h = s.pairs.halo;
  ASSERT_GT(h.size(), 10u);
  // A step's drift: every owner changes its disks, then packs; then every part copies out.
  for (std::size_t i = 0; i < d.size(); ++i) {
    for (auto* v : {&d.x, &d.y, &d.vx, &d.vy, &d.omega, &d.vpx, &d.vpy}) (*v)[i] += 1.0 / 3.0;
  }
  for (int part = 0; part < 2; ++part) pack_mid_step(d, h, part);
  for (int part = 0; part < 2; ++part) unpack_mid_step(d, h, part);
  expect_ghosts_equal(d, h);
  // The kick: the final velocities.
  for (std::size_t i = 0; i < d.size(); ++i) {
    d.vx[i] *= 0.7;
    d.vy[i] *= 1.3;
  }
  for (int part = 0; part < 2; ++part) pack_final(d, h, part);
  for (int part = 0; part < 2; ++part) unpack_final(d, h, part);
  expect_ghosts_equal(d, h);
  // One thread on one part: no ghosts, every pair reads j itself.
  plan_parts(d, s.pairs, even_parts(d.size(), 1));
  EXPECT_EQ(h.size(), 0u);
  EXPECT_TRUE(std::equal(s.pairs.j.begin(), s.pairs.j.end(), s.pairs.j_slot.begin()));
}

}  // namespace
}  // namespace granstab::dynamic
