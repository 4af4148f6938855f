// The ETA of runs with no known end (common/progress.hpp, issue #4 item 5): the decay estimate
// recovers the steps left of an exponentially decaying residual, says nothing while the residual
// does not decay, and the line is labelled as an estimate.
#include <gtest/gtest.h>

#include <cmath>

#include "common/progress.hpp"

namespace granstab {
namespace {

TEST(DecayEstimate, RecoversTheStepsLeftOfAnExponentialDecay) {
  DecayEstimate e;
  // ratio = 1e4 exp(-step / 1000): reaches 1 at step 1000 ln(1e4) = 9210.3.
  for (int step = 0; step <= 4000; step += 200) e.add(step, 1e4 * std::exp(-step / 1000.0));
  ASSERT_TRUE(e.steps_left().has_value());
  EXPECT_NEAR(*e.steps_left(), 1000.0 * std::log(1e4) - 4000.0, 1e-6);
}

TEST(DecayEstimate, NoEstimateWithoutDecayOrWithTooFewChecks) {
  DecayEstimate e;
  e.add(0, 10.0);
  e.add(200, 5.0);
  EXPECT_FALSE(e.steps_left().has_value());
  DecayEstimate flat;
  for (int step = 0; step <= 2000; step += 200) flat.add(step, 3.0);
  EXPECT_FALSE(flat.steps_left().has_value());  // zero slope: no honest estimate
  DecayEstimate growing;
  for (int step = 0; step <= 2000; step += 200) growing.add(step, 1.0 + step);
  EXPECT_FALSE(growing.steps_left().has_value());
}

TEST(DecayEstimate, UsesTheLaterHalfOfTheChecks) {
  DecayEstimate e;
  // A fast transient (the free fall) then a slow decay: the estimate follows the slow one.
  for (int step = 0; step < 1000; step += 100) e.add(step, 1e12 * std::exp(-step / 50.0));
  const double at_1000 = 1e12 * std::exp(-1000 / 50.0);
  for (int step = 1000; step <= 20000; step += 100) {
    e.add(step, at_1000 * std::exp(-(step - 1000) / 10000.0));
  }
  const double ratio_now = at_1000 * std::exp(-19000 / 10000.0);
  EXPECT_NEAR(*e.steps_left(), 10000.0 * std::log(ratio_now), 1e-3);
}

TEST(Progress, TheEstimatedEtaIsLabelledAsAnEstimate) {
  EXPECT_EQ(Progress::format_estimated("prepare", 12000, 3.0, 8.0, "residual decay", "Phi 0.8"),
            "prepare: 12000  elapsed 3 s  ETA ~8 s (estimate: residual decay)  Phi 0.8");
  EXPECT_EQ(Progress::format_estimated("prepare", 200, 0.1, std::nullopt, "residual decay", ""),
            "prepare: 200  elapsed 0 s  ETA ? (estimate: residual decay)");
  // A static run with no --q-max has no end to estimate towards: no empty "(estimate: )".
  EXPECT_EQ(Progress::format_estimated("probe", 445, 29.0, std::nullopt, "", "q 0.42"),
            "probe: 445  elapsed 29 s  ETA ?  q 0.42");
}

}  // namespace
}  // namespace granstab
