// The predictor's LCP rounds (SolverOptions::max_lcp_rounds): a round that sets the statuses the
// round before it set retraces that round's iterates, cycle and LCP, so the loop stops there. On
// periodic-n100 at mu = 0.5, dq = 1e-2 eleven attempts near q1 cycle that way (five iterations per
// round); the run must not depend on how many rounds are allowed beyond the second.
#include <gtest/gtest.h>

#include <filesystem>

#include "common/io/configuration_file.hpp"
#include "static/q1.hpp"

namespace granstab::statics {
namespace {

StabilityResult q1_with_rounds(int rounds) {
  Configuration config = read_configuration(std::filesystem::path(GRANSTAB_SAMPLES_DIR) /
                                            "periodic-n100-k1e4.granstab");
  config.material.mu = 0.5;
  Q1Options o;
  o.dq = 1e-2;
  o.hill_every = 0;
  o.solver.max_lcp_rounds = rounds;
  return find_q1(config, o);
}

TEST(LcpRounds, ARoundThatRepeatsTheLastEndsTheLoop) {
  const StabilityResult three = q1_with_rounds(3), thirty = q1_with_rounds(30);
  // Without the stop, each of the repeating attempts runs all its rounds: 27 x 5 iterations more
  // in each at 30 rounds.
  EXPECT_EQ(three.timings.status_iterations, thirty.timings.status_iterations);
  EXPECT_EQ(three.attempts, thirty.attempts);
  EXPECT_EQ(three.q1, thirty.q1);
  EXPECT_EQ(three.criterion, thirty.criterion);
  ASSERT_EQ(three.curve.size(), thirty.curve.size());
  for (std::size_t i = 0; i < three.curve.size(); ++i) {
    EXPECT_EQ(three.curve[i].load, thirty.curve[i].load) << "row " << i;
    EXPECT_EQ(three.curve[i].n_sliding, thirty.curve[i].n_sliding) << "row " << i;
  }
  // The case is there: the run meets cycles that its LCP rounds do not settle.
  EXPECT_GT(three.rejected.count("predictor: cycle"), 0u);
}

}  // namespace
}  // namespace granstab::statics
