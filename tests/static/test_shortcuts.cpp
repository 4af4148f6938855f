// Shortcuts of the status loop and of the corrector on periodic-n100 (dq = 1e-2, Hill off): each
// must leave the path as it was and save work, checked against a run without it.
// - LcpRounds (SolverOptions::max_lcp_rounds): a round that sets the statuses the round before it
//   set retraces that round's iterates, cycle and LCP, so the loop stops there. At mu = 0.5 eleven
//   attempts near q1 cycle that way (five iterations per round): the run must not depend on how
//   many rounds are allowed beyond the second.
// - CorrectorKinks (SolverOptions::kink_trials, static/corrector.cpp): at the sample's own
//   mu = 0.15 halving alone crept towards a contact reaching the cone, one Newton iteration and LU
//   per halving of |R| (ten iterations in one step), where the point just past it converges in two.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>

#include "common/io/configuration_file.hpp"
#include "static/q1.hpp"

namespace granstab::statics {
namespace {

StabilityResult periodic_n100_q1(double mu, const std::function<void(SolverOptions&)>& set) {
  Configuration config = read_configuration(std::filesystem::path(GRANSTAB_SAMPLES_DIR) /
                                            "periodic-n100-k1e4.granstab");
  config.material.mu = mu;
  Q1Options o;
  o.dq = 1e-2;
  o.hill_every = 0;
  set(o.solver);
  return find_q1(config, o);
}

// The same accepted states, q1 and criterion; strains to the corrector's tolerance.
void expect_same_path(const StabilityResult& a, const StabilityResult& b) {
  EXPECT_EQ(a.q1, b.q1);
  EXPECT_EQ(a.criterion, b.criterion);
  EXPECT_EQ(a.attempts, b.attempts);
  ASSERT_EQ(a.curve.size(), b.curve.size());
  for (std::size_t i = 0; i < a.curve.size(); ++i) {
    EXPECT_EQ(a.curve[i].load, b.curve[i].load) << "row " << i;
    EXPECT_EQ(a.curve[i].n_sliding, b.curve[i].n_sliding) << "row " << i;
    EXPECT_NEAR(a.curve[i].eps2, b.curve[i].eps2, 1e-8 * std::abs(b.curve[i].eps2)) << "row " << i;
  }
}

TEST(LcpRounds, ARoundThatRepeatsTheLastEndsTheLoop) {
  const StabilityResult three =
      periodic_n100_q1(0.5, [](SolverOptions& s) { s.max_lcp_rounds = 3; });
  const StabilityResult thirty =
      periodic_n100_q1(0.5, [](SolverOptions& s) { s.max_lcp_rounds = 30; });
  expect_same_path(three, thirty);
  // Without the stop, each of the repeating attempts runs all its rounds: 27 x 5 iterations more
  // in each at 30 rounds.
  EXPECT_EQ(three.timings.status_iterations, thirty.timings.status_iterations);
  // The case is there: the run meets cycles that its LCP rounds do not settle.
  EXPECT_GT(three.rejected.count("predictor: cycle"), 0u);
}

TEST(CorrectorKinks, TheSamePathInFewerNewtonIterations) {
  const StabilityResult kinks = periodic_n100_q1(0.15, [](SolverOptions&) {});
  const StabilityResult halving =
      periodic_n100_q1(0.15, [](SolverOptions& s) { s.kink_trials = 0; });
  expect_same_path(kinks, halving);
  std::printf("Newton iterations: %d with kink trials, %d halving only\n",
              kinks.timings.newton_iterations, halving.timings.newton_iterations);
  // 106 against 130 in the Release build; a tenth below halving's count leaves room for other
  // builds' round-off while halving alone stays above it.
  EXPECT_LT(kinks.timings.newton_iterations, 0.9 * halving.timings.newton_iterations);
}

}  // namespace
}  // namespace granstab::statics
