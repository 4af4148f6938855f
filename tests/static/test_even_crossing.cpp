// STATIC.md §S3.4 (b) made robust: det K keeps its sign when an even number of eigenvalues cross
// zero within one step; the count of real negative eigenvalues of K (through the LDL^T inertia of
// the symmetric part, then the eigenvalues of K nearest 0) does not.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "static/hill.hpp"
#include "static/linear_solvers.hpp"
#include "static/load_step.hpp"
#include "static/q1.hpp"

namespace granstab::statics {
namespace {

// Block diagonal: 2 x 2 blocks [[a, b], [-b, a]] (eigenvalues a +- i b, symmetric part a I) and
// [[a, c], [c, a]] (eigenvalues a +- c), then a diagonal tail.
SparseMatrix blocks(const std::vector<std::array<double, 3>>& rotation,
                    const std::vector<std::array<double, 2>>& symmetric,
                    const std::vector<double>& tail) {
  std::vector<Eigen::Triplet<double>> t;
  int n = 0;
  for (const auto& [a, b, unused] : rotation) {
    (void)unused;
    t.emplace_back(n, n, a);
    t.emplace_back(n, n + 1, b);
    t.emplace_back(n + 1, n, -b);
    t.emplace_back(n + 1, n + 1, a);
    n += 2;
  }
  for (const auto& [a, c] : symmetric) {
    t.emplace_back(n, n, a);
    t.emplace_back(n, n + 1, c);
    t.emplace_back(n + 1, n, c);
    t.emplace_back(n + 1, n + 1, a);
    n += 2;
  }
  for (double d : tail) t.emplace_back(n, n, d), ++n;
  SparseMatrix k(n, n);
  k.setFromTriplets(t.begin(), t.end());
  return k;
}

void expect_counts(const SparseMatrix& k, int symmetric, int real) {
  LuFactor lu;
  ASSERT_TRUE(lu.factorize(k));
  for (const LuFactor* factor : {static_cast<const LuFactor*>(&lu),
                                 static_cast<const LuFactor*>(nullptr)}) {  // Arnoldi, dense
    const NegativeEigenvalues e = negative_eigenvalues(k, factor);
    ASSERT_TRUE(e.ok);
    EXPECT_EQ(e.symmetric, symmetric) << (factor ? "arnoldi" : "dense");
    EXPECT_EQ(e.real, real) << (factor ? "arnoldi" : "dense");
  }
}

TEST(NegativeEigenvalues, CountsRealNegativeEigenvaluesNotTheDeterminantSign) {
  std::vector<double> tail;
  for (int i = 0; i < 30; ++i) tail.push_back(1.0 + i);
  // Two negative eigenvalues (-2 +- 0.5): det > 0.
  expect_counts(blocks({}, {{-2.0, 0.5}}, tail), 2, 2);
  // [[0.5, 6], [-4, 0.5]]: complex eigenvalues 0.5 +- i sqrt(24), symmetric part [[0.5, 1],
  // [1, 0.5]] with one negative eigenvalue: Hill < 0 and still no real negative eigenvalue.
  SparseMatrix k = blocks({{0.5, 4.0, 0.0}}, {}, tail);
  k.coeffRef(0, 1) = 6.0;
  k.coeffRef(1, 0) = -4.0;
  expect_counts(k, 1, 0);
  // Positive definite symmetric part: 0 without an eigensolver.
  expect_counts(blocks({{1.0, 5.0, 0.0}}, {{3.0, 1.0}}, tail), 0, 0);
}

// symmetric_part's mirror path (a structurally symmetric pattern) against the plain sum
// 0.5 (K + K^T): the same pattern and the same bits; a pattern without its mirror takes the sum.
TEST(NegativeEigenvalues, SymmetricPartOfAMirroredPatternIsThePlainSumBitForBit) {
  const int n = 40;
  std::vector<Eigen::Triplet<double>> symmetric_pattern, lopsided;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if ((i * 7 + j * 7 + i * j) % 5 != 0 && i != j) continue;  // symmetric in (i, j)
      // Unequal values at (i, j) and (j, i), an explicit zero among them.
      const double value = i == 3 && j == 5 ? 0.0 : std::sin(1.0 + i + 0.37 * j);
      symmetric_pattern.emplace_back(i, j, value);
      if (!(i == 1 && j > 1)) lopsided.emplace_back(i, j, value);  // row 1 right of the diagonal
    }
  for (const auto* triplets : {&symmetric_pattern, &lopsided}) {
    SparseMatrix k(n, n);
    k.setFromTriplets(triplets->begin(), triplets->end());
    k.makeCompressed();
    for (int round = 0; round < 2; ++round) {  // a fresh pattern, then the kept one
      const SparseMatrix plain = 0.5 * (k + SparseMatrix(k.transpose()));
      const SparseMatrix s = symmetric_part(k);
      ASSERT_EQ(s.nonZeros(), plain.nonZeros());
      for (Eigen::Index e = 0; e < s.nonZeros(); ++e) {
        EXPECT_EQ(s.innerIndexPtr()[e], plain.innerIndexPtr()[e]);
        EXPECT_EQ(std::memcmp(s.valuePtr() + e, plain.valuePtr() + e, sizeof(double)), 0);
      }
      for (Eigen::Index j = 0; j <= n; ++j)
        EXPECT_EQ(s.outerIndexPtr()[j], plain.outerIndexPtr()[j]);
      k.coeffs() *= -1.5;  // other values, the same pattern
    }
  }
}

// The LDL^T keeps its analysis for a repeated pattern: the count must follow the values of each
// matrix (a stale numeric factor would repeat the first count), and another pattern of the same
// size and number of entries must be analysed afresh.
TEST(NegativeEigenvalues, SymmetricCountFollowsTheValuesOfARepeatedPattern) {
  const std::vector<double> tail = {1.0, 2.0, 3.0, 4.0};
  // [[a, c], [c, a]] has eigenvalues a +- c.
  EXPECT_EQ(negative_eigenvalue_count_symmetric(blocks({}, {{1.0, 0.5}, {1.0, 0.5}}, tail)), 0);
  EXPECT_EQ(negative_eigenvalue_count_symmetric(blocks({}, {{1.0, 2.0}, {1.0, 0.5}}, tail)), 1);
  EXPECT_EQ(negative_eigenvalue_count_symmetric(blocks({}, {{-1.0, 2.0}, {-3.0, 0.5}}, tail)), 3);
  EXPECT_EQ(negative_eigenvalue_count_symmetric(blocks({}, {{1.0, 0.5}, {1.0, 0.5}}, tail)), 0);
  // The same size and number of entries, the off-diagonal pair elsewhere: rows 0 and 5 coupled.
  SparseMatrix other = blocks({}, {}, {1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0});
  other.coeffRef(0, 5) = 3.0;
  other.coeffRef(5, 0) = 3.0;
  other.coeffRef(2, 3) = 0.5;
  other.coeffRef(3, 2) = 0.5;
  other.makeCompressed();
  EXPECT_EQ(negative_eigenvalue_count_symmetric(other), 1);
  EXPECT_EQ(negative_eigenvalue_count_symmetric(blocks({}, {{1.0, 0.5}, {1.0, 2.0}}, tail)), 1);
}

// A witness x with x^T K x < 0 shows the symmetric part indefinite without its LDL^T: the same
// eigenvalues are then counted, the inertia is left uncounted, and the LDL^T's own witness (from
// its first negative pivot) proves what it should. A witness that shows nothing is not trusted.
TEST(NegativeEigenvalues, AWitnessOfAnIndefiniteSymmetricPartSparesTheInertia) {
  std::vector<double> tail;
  for (int i = 0; i < 30; ++i) tail.push_back(1.0 + i);
  SparseMatrix k = blocks({{0.5, 4.0, 0.0}}, {{-2.0, 0.5}}, tail);
  k.coeffRef(0, 1) = 6.0;
  k.coeffRef(1, 0) = -4.0;
  LuFactor lu;
  ASSERT_TRUE(lu.factorize(k));
  const NegativeEigenvalues counted = negative_eigenvalues(k, &lu);
  ASSERT_TRUE(counted.ok);
  EXPECT_EQ(counted.symmetric, 3);  // 0.5 - 1 (rotation block), -2 +- 0.5
  EXPECT_EQ(counted.real, 2);
  ASSERT_EQ(counted.witness.size(), k.rows());
  EXPECT_LT(counted.witness.dot(k * counted.witness), 0.0);
  EXPECT_TRUE(proves_indefinite(k, counted.witness));

  const NegativeEigenvalues witnessed = negative_eigenvalues(k, &lu, &counted.witness);
  ASSERT_TRUE(witnessed.ok);
  EXPECT_EQ(witnessed.symmetric, indefinite_uncounted);
  EXPECT_EQ(witnessed.real, counted.real);
  EXPECT_EQ(witnessed.nearest_zero, counted.nearest_zero);

  // A positive definite symmetric part: no vector proves otherwise, the LDL^T decides.
  const SparseMatrix definite = blocks({{1.0, 5.0, 0.0}}, {{3.0, 1.0}}, tail);
  const Eigen::VectorXd probe = Eigen::VectorXd::Ones(definite.rows());
  EXPECT_FALSE(proves_indefinite(definite, probe));
  const NegativeEigenvalues pd = negative_eigenvalues(definite, nullptr, &probe);
  EXPECT_EQ(pd.symmetric, 0);
  EXPECT_EQ(pd.real, 0);
  EXPECT_EQ(pd.witness.size(), 0);
  // x^T K x = 0 within round-off (an antisymmetric pair only) proves nothing either.
  Eigen::VectorXd flat = Eigen::VectorXd::Zero(definite.rows());
  flat[0] = 1.0;
  SparseMatrix rotation = blocks({{0.0, 5.0, 0.0}}, {}, tail);
  EXPECT_FALSE(proves_indefinite(rotation, flat));
}

// The Arnoldi of a state started from the last state's Ritz vectors (arnoldi_start): along a path
// of nearby matrices on which two real eigenvalues cross zero, the same counts and eigenvalues as
// a start from Spectra's fixed vector, in fewer solves.
TEST(NegativeEigenvalues, ArnoldiStartedFromTheLastStateFindsTheSameInFewerSolves) {
  NegativeEigenvalueStatistics& statistics = negative_eigenvalue_statistics();
  long cold_solves = 0, warm_solves = 0;
  Eigen::VectorXd start;
  for (int state = 0; state < 12; ++state) {
    const double a = 0.65 - 0.1 * state;  // a - 0.3 and a + 0.3 cross zero on the way
    std::vector<double> tail;
    for (int i = 0; i < 80; ++i) tail.push_back((1.0 + i) * (1.0 + 0.01 * state));
    SparseMatrix k = blocks({{0.5, 4.0, 0.0}}, {{-2.0, 0.5}, {a, 0.3}}, tail);
    k.coeffRef(0, 1) = 6.0;  // the symmetric part indefinite: the Arnoldi runs
    k.coeffRef(1, 0) = -4.0;
    LuFactor lu;
    ASSERT_TRUE(lu.factorize(k));
    long before = statistics.arnoldi_solves;
    const NegativeEigenvalues cold = negative_eigenvalues(k, &lu);
    cold_solves += statistics.arnoldi_solves - before;
    before = statistics.arnoldi_solves;
    const NegativeEigenvalues warm =
        negative_eigenvalues(k, &lu, nullptr, start.size() > 0 ? &start : nullptr);
    warm_solves += statistics.arnoldi_solves - before;
    ASSERT_TRUE(cold.ok && warm.ok);
    const int expected = 2 + (a < 0.3) + (a < -0.3);  // -2 +- 0.5 throughout
    EXPECT_EQ(cold.real, expected) << "state " << state;
    EXPECT_EQ(warm.real, expected) << "state " << state;
    EXPECT_NEAR(warm.nearest_zero, cold.nearest_zero, 1e-9 * cold.nearest_zero);
    ASSERT_EQ(warm.arnoldi_start.size(), k.rows());
    start = warm.arnoldi_start;
  }
  EXPECT_LT(warm_solves, cold_solves);
  std::printf("Arnoldi solves along the path: %ld from the fixed start, %ld warm\n", cold_solves,
              warm_solves);
}

// The Arnoldi screens at a loose tolerance and reruns at the tight one only where an eigenvalue
// found has a negative real part (negative_eigenvalues.cpp): every count comes from the tight run,
// and where the screening decides alone its nearest_zero is still that of K.
TEST(NegativeEigenvalues, TheTightArnoldiDecidesWhereAValueHasANegativeRealPart) {
  NegativeEigenvalueStatistics& statistics = negative_eigenvalue_statistics();
  std::vector<double> tail;
  for (int i = 0; i < 40; ++i) tail.push_back(1.0 + 0.37 * i);
  // The number of tight runs, after checking the count and the eigenvalue nearest 0.
  const auto run = [&](const SparseMatrix& k, int real, double nearest) -> long {
    LuFactor lu;
    EXPECT_TRUE(lu.factorize(k));
    const long confirmed = statistics.arnoldi_confirmed;
    const NegativeEigenvalues e = negative_eigenvalues(k, &lu);
    EXPECT_TRUE(e.ok);
    EXPECT_EQ(e.real, real);
    EXPECT_NEAR(e.nearest_zero, nearest, 1e-6 * nearest);
    return statistics.arnoldi_confirmed - confirmed;
  };
  // Indefinite symmetric part, every eigenvalue of K with a positive real part (0.3 +- i sqrt(24)
  // nearest 0 after the tail's 1): the screening decides.
  SparseMatrix stable = blocks({{0.3, 4.0, 0.0}}, {}, tail);
  stable.coeffRef(0, 1) = 6.0;
  stable.coeffRef(1, 0) = -4.0;
  EXPECT_EQ(run(stable, 0, 1.0), 0);
  // Flutter (-0.3 +- 0.5 i): no real negative eigenvalue, but the tight run decides that.
  const double flutter = std::hypot(0.3, 0.5);
  EXPECT_EQ(run(blocks({{-0.3, 0.5, 0.0}}, {}, tail), 0, flutter), 1);
  // Two real negative eigenvalues near 0 (-0.2 +- 0.1) beside the flutter pair.
  EXPECT_EQ(run(blocks({{-0.3, 0.5, 0.0}}, {{-0.2, 0.1}}, tail), 2, 0.1), 1);
}

// Three disks of radius 1/2 per period along x (spacing d = 1 - F/K_N), rotations and e2 fixed,
// the translation pinned on disk 0: the transverse displacements of disks 1 and 2 have the
// stiffness matrix k [[2, -1], [-1, 2]] with k = K_T - F/d, eigenvalues k and 3k. Both cross zero
// together at F* = K_T / (1 + K_T/K_N): det K never changes sign.
Network three_disk_chain(double force, double k_t) {
  Network net;
  net.boundary = Boundary::periodic;
  net.material.k_n = 1e3;
  net.material.k_t = k_t;
  net.material.mu = 0.5;
  const double d = 1.0 - force / net.material.k_n;
  net.length = {3 * d, 3.0};
  for (int i = 0; i < 3; ++i) {
    net.x.push_back(0.5 + i * d);
    net.y.push_back(1.5);
    net.radius.push_back(0.5);
    net.theta.push_back(0.0);
  }
  net.contacts.add(0, 1, 0, 0);
  net.contacts.add(1, 2, 0, 0);
  net.contacts.add(2, 0, 1, 0);
  net.constraints.cell_free = {true, false};
  net.constraints.rotation_fixed.assign(3, 1);
  net.loading.sigma = {force / net.length[1], 0.0};
  prepare(net, SolverOptions{});
  return net;
}

TEST(NegativeEigenvalues, TwoTransverseModesCrossingTogetherAreABifurcation) {
  const double k_t = 50.0, k_n = 1e3, f_star = k_t / (1.0 + k_t / k_n);
  const Network net = three_disk_chain(10.0, k_t);
  const double l2 = net.length[1];
  const LoadPath axial = [l2](Network& n, double force) { n.loading.sigma = {force / l2, 0.0}; };
  Q1Options o;
  o.dq = 1.0;
  o.dq_min = 1e-6;
  o.load_stop = 2.0 * f_star;
  const StabilityResult r = trace_to_instability(net, 10.0, axial, net.length, o);
  EXPECT_EQ(r.criterion, Criterion::bifurcation) << r.detail;
  EXPECT_LE(r.q1_bracket[0], f_star);
  EXPECT_GE(r.q1_bracket[1], f_star);
  EXPECT_LT(r.q1_bracket[1] - r.q1_bracket[0], 2e-6);
  for (const CurvePoint& p : r.curve) EXPECT_EQ(p.determinant_sign, 1);
  // Adaptive steps (the default) grow far beyond dq on the way (no status event, the symmetric
  // part positive definite) and step over F*: the end state's count rejects that step, and the
  // crossing is bracketed from dq as with fixed steps.
  EXPECT_EQ(r.step_control, StepControl::adaptive);
  EXPECT_GT(r.interpolated_rows, 0);
  Q1Options fixed_steps = o;
  fixed_steps.steps = StepControl::fixed;
  const StabilityResult f = trace_to_instability(net, 10.0, axial, net.length, fixed_steps);
  std::printf("adaptive: %d attempts, q1 = %.9f; fixed: %d attempts, q1 = %.9f; F* = %.9f\n",
              r.attempts, r.q1, f.attempts, f.q1, f_star);
  EXPECT_EQ(f.criterion, Criterion::bifurcation);
  EXPECT_NEAR(r.q1, f.q1, 2e-6);
  EXPECT_LT(r.attempts, f.attempts);
  // The determinant sign alone walks through F* to the stop.
  o.count_negative_eigenvalues = false;
  const StabilityResult blind = trace_to_instability(net, 10.0, axial, net.length, o);
  EXPECT_EQ(blind.criterion, Criterion::none) << blind.detail;
  EXPECT_GT(blind.q1, 1.5 * f_star);
}

}  // namespace
}  // namespace granstab::statics
