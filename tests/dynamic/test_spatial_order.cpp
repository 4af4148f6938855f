// Renumbering disks in space-filling order changes nothing physical: the same state, the same
// contacts with their tangential state, the same evolution up to round-off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "dynamic/spatial_order.hpp"
#include "helpers.hpp"

namespace granstab {
namespace {

TEST(SpatialOrder, RenumberedSampleEvolvesIdentically) {
  Configuration c = testing::dense_packing(64, Material::from_kappa(1e3, 1.0, 0.3, 0.7), 4);
  c.stage.sigma_ext = {1.0, 1.3};  // load it so that it moves and contacts slide
  Engine warm(c);
  warm.run(300);
  c = warm.configuration();
  ASSERT_GT(c.contacts.size(), 50u);

  const std::vector<std::int32_t> order = spatial_order(c);
  const Configuration sorted = renumbered(c, order);
  // Consecutive disks are close in space (the point of the order), unlike the random
  // numbering of a sample grown from a random gas.
  const auto mean_step = [&](const Configuration& s) {
    double sum = 0.0;
    for (std::size_t k = 1; k < s.disks.size(); ++k) {
      double dx = std::abs(s.disks.x[k] - s.disks.x[k - 1]);
      double dy = std::abs(s.disks.y[k] - s.disks.y[k - 1]);
      dx = std::min(dx, s.cell.length[0] - dx);
      dy = std::min(dy, s.cell.length[1] - dy);
      sum += std::hypot(dx, dy);
    }
    return sum / (s.disks.size() - 1);
  };
  EXPECT_LT(mean_step(sorted), 0.5 * mean_step(c));

  Engine a(c), b(sorted);
  const auto sa = a.stress(), sb = b.stress();
  for (int p = 0; p < 2; ++p) {
    for (int q = 0; q < 2; ++q) EXPECT_NEAR(sa[p][q], sb[p][q], 1e-12);
  }
  a.run(500);
  b.run(500);
  for (std::size_t k = 0; k < order.size(); ++k) {
    EXPECT_NEAR(b.x()[k], a.x()[order[k]], 1e-9);
    EXPECT_NEAR(b.y()[k], a.y()[order[k]], 1e-9);
    EXPECT_NEAR(b.omega()[k], a.omega()[order[k]], 1e-9);
  }
  EXPECT_EQ(a.contact_count(), b.contact_count());
  EXPECT_NEAR(a.stress()[1][1], b.stress()[1][1], 1e-9);
}

TEST(SpatialOrder, RejectsNonPermutation) {
  Configuration c = testing::random_gas(10, 0.2, Material{}, 1);
  EXPECT_THROW(renumbered(c, {0, 1, 2}), std::invalid_argument);
  EXPECT_THROW(renumbered(c, {0, 0, 2, 3, 4, 5, 6, 7, 8, 9}), std::invalid_argument);
}

}  // namespace
}  // namespace granstab
