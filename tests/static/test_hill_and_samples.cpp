// The Hill indicator on both code paths, and T8 on the shipped samples: q1 <= q_max of the
// rigid-limit LP (STATIC.md §S4 T8).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "common/io/configuration_file.hpp"
#include "static/hill.hpp"
#include "static/q1.hpp"
#include "static/rigid_limit.hpp"

namespace granstab::statics {
namespace {

// 1D Dirichlet Laplacian (eigenvalues 2 - 2 cos(k pi / (n + 1))) shifted by -shift, plus an
// antisymmetric part that the Hill indicator must ignore.
SparseMatrix shifted_laplacian(int n, double shift) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0 - shift);
    if (i + 1 < n) {
      t.emplace_back(i, i + 1, -1.0 + 0.3);
      t.emplace_back(i + 1, i, -1.0 - 0.3);
    }
  }
  SparseMatrix k(n, n);
  k.setFromTriplets(t.begin(), t.end());
  return k;
}

TEST(HillIndicator, DenseAndLanczosPathsFindTheSmallestEigenvalue) {
  for (int n : {50, 600}) {  // below and above the dense threshold
    const double lowest = 2.0 - 2.0 * std::cos(M_PI / (n + 1));
    for (double shift : {0.0, 2.0 * lowest, 1.0}) {
      const HillResult h = hill_indicator(shifted_laplacian(n, shift));
      ASSERT_TRUE(h.ok) << n << " " << shift;
      EXPECT_NEAR(h.min_eigenvalue, lowest - shift, 1e-8 * (1.0 + std::abs(lowest - shift)))
          << n << " " << shift;
      // The mode is the first sine: no sign change.
      const double first = h.mode[0];
      for (int i = 0; i < n; ++i) EXPECT_GT(h.mode[i] * first, 0.0);
    }
  }
}

const std::filesystem::path samples = std::filesystem::path(GRANSTAB_SAMPLES_DIR);

void expect_q1_below_rigid_limit(const std::string& name, double dq) {
  const Configuration config = read_configuration(samples / name);
  Q1Options o;
  o.dq = dq;
  o.dq_min = 1e-6;
  o.hill = false;
  const StabilityResult r = find_q1(config, o);
  const RigidLimitResult rigid = rigid_limit(config);
  ASSERT_TRUE(rigid.solved) << rigid.status;
  std::printf("%s: q1 = %.6f (%s, %zu sliding), q_max_rigid = %.6f (%s)\n", name.c_str(), r.q1,
              criterion_name(r.criterion), r.sliding_at_q1.size(), rigid.q_max,
              rigid.status.c_str());
  EXPECT_NE(r.criterion, Criterion::none);
  EXPECT_LE(r.q1, rigid.q_max);
}

TEST(RigidLimitBound, HoldsOnTheShippedSamples) {
  expect_q1_below_rigid_limit("tiny-triangular-periodic.granstab", 0.2);
  expect_q1_below_rigid_limit("tiny-square-walls.granstab", 2.0);
  expect_q1_below_rigid_limit("periodic-n100-k1e4.granstab", 0.01);
}

}  // namespace
}  // namespace granstab::statics
