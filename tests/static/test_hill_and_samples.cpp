// The Hill indicator on both code paths, and T8 on the shipped samples: q1 <= q_max of the
// rigid-limit LP (STATIC.md §S4 T8).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <vector>

#include <Eigen/Core>

#include "dense_reference.hpp"
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
  for (int n : {30, 600}) {  // below and above the dense threshold
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

// Warm-started from the solution of a nearby matrix (as along a load path: the eigenvalue moved
// up or down, the mode nearly the same), the same eigenvalue as the cold and the dense solve.
TEST(HillIndicator, WarmStartFindsTheSameEigenvalue) {
  const int n = 300;
  const double lowest = 2.0 - 2.0 * std::cos(M_PI / (n + 1));
  const HillResult before = hill_indicator(shifted_laplacian(n, 0.5 * lowest));
  ASSERT_TRUE(before.ok);
  for (double shift : {0.0, 0.49 * lowest, 0.51 * lowest, 3.0 * lowest, 0.2}) {
    const SparseMatrix k = shifted_laplacian(n, shift);
    const HillResult warm = hill_indicator(k, &before), cold = hill_indicator(k);
    const Eigen::VectorXd dense = dense_reference::symmetric_eigenvalues(
        Eigen::MatrixXd(0.5 * (k + SparseMatrix(k.transpose()))));
    ASSERT_TRUE(warm.ok && cold.ok) << shift;
    EXPECT_NEAR(warm.min_eigenvalue, dense[0], 1e-9) << shift;
    EXPECT_NEAR(cold.min_eigenvalue, dense[0], 1e-9) << shift;
  }
}

// The Hill indicator is logged only: its stride changes no other column of the curve.
TEST(HillIndicator, ItsStrideLeavesThePathUnchanged) {
  const Configuration config = read_configuration(std::filesystem::path(GRANSTAB_SAMPLES_DIR) /
                                                  "periodic-n100-k1e4.granstab");
  std::vector<StabilityResult> runs;
  for (std::size_t every : {0, 1, 3}) {
    Q1Options o;
    o.load_stop = 0.1;
    o.hill_every = every;
    runs.push_back(find_q1(config, o));
  }
  ASSERT_EQ(runs[0].curve.size(), runs[1].curve.size());
  ASSERT_EQ(runs[0].curve.size(), runs[2].curve.size());
  std::size_t state = 0;  // the stride counts accepted states, not interpolated rows
  for (std::size_t k = 0; k < runs[0].curve.size(); ++k) {
    for (const auto& r : {runs[1], runs[2]}) {
      EXPECT_EQ(r.curve[k].q, runs[0].curve[k].q);
      EXPECT_EQ(r.curve[k].eps2, runs[0].curve[k].eps2);
      EXPECT_EQ(r.curve[k].n_sliding, runs[0].curve[k].n_sliding);
      EXPECT_EQ(r.curve[k].interpolated, runs[0].curve[k].interpolated);
    }
    EXPECT_TRUE(std::isnan(runs[0].curve[k].hill));
    if (runs[0].curve[k].interpolated) {
      EXPECT_TRUE(std::isnan(runs[1].curve[k].hill));
      continue;
    }
    EXPECT_TRUE(std::isfinite(runs[1].curve[k].hill));
    EXPECT_EQ(std::isfinite(runs[2].curve[k].hill), state % 3 == 0) << k;
    if (state++ % 3 == 0) {
      EXPECT_NEAR(runs[2].curve[k].hill, runs[1].curve[k].hill,
                  1e-9 * std::abs(runs[1].curve[k].hill));
    }
  }
}

const std::filesystem::path samples = std::filesystem::path(GRANSTAB_SAMPLES_DIR);

void expect_q1_below_rigid_limit(const std::string& name, double dq) {
  const Configuration config = read_configuration(samples / name);
  Q1Options o;
  o.dq = dq;
  o.dq_min = 1e-6;
  o.hill_every = 0;
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
