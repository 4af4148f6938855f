// Step control between status events (Q1Options::step_growth, issue #18 item 3) on the shipped
// N = 100 sample: longer steps where no contact changes status give the q1 of fixed steps within
// its bracket and the step error, with fewer computed states; the states at multiples of dq inside
// a long step are marked and lie between the computed states on both sides.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "common/io/configuration_file.hpp"
#include "static/q1.hpp"

namespace {

using namespace granstab;

Configuration sample() {
  return read_configuration(std::filesystem::path(GRANSTAB_SAMPLES_DIR) /
                            "periodic-n100-k1e4.granstab");
}

statics::StabilityResult run(double mu, int growth) {
  Configuration config = sample();
  config.material.mu = mu;
  statics::Q1Options o;
  o.dq = 1e-3;
  o.hill_every = 0;
  o.step_growth = growth;
  return statics::find_q1(config, o);
}

TEST(StepGrowth, SameQ1WithFewerComputedStatesAndMarkedInterpolation) {
  const statics::StabilityResult fixed = run(0.5, 1);
  const statics::StabilityResult grown = run(0.5, 16);
  ASSERT_NE(fixed.criterion, statics::Criterion::none);
  EXPECT_EQ(grown.criterion, fixed.criterion);
  // Within the fixed run's bracket plus one step dq (the path error of the longer event-free
  // steps is geometric, far below it; measured: the same q1 to the bit on this sample).
  EXPECT_GE(grown.q1, fixed.q1_bracket[0] - 1e-3);
  EXPECT_LE(grown.q1, fixed.q1_bracket[1] + 1e-3);
  EXPECT_LT(grown.steps, fixed.steps * 3 / 4);
  // Every multiple of dq is on the curve, computed or interpolated, as with fixed steps.
  const auto on_grid = [](const statics::StabilityResult& r) {
    return std::count_if(r.curve.begin(), r.curve.end(), [](const statics::CurvePoint& p) {
      return std::abs(p.load / 1e-3 - std::round(p.load / 1e-3)) < 1e-6;
    });
  };
  EXPECT_EQ(on_grid(grown), on_grid(fixed));
  int interpolated = 0;
  for (std::size_t k = 1; k + 1 < grown.curve.size(); ++k) {
    const statics::CurvePoint& p = grown.curve[k];
    if (!p.interpolated) continue;
    ++interpolated;
    std::size_t a = k, b = k;
    while (grown.curve[a].interpolated) --a;
    while (grown.curve[b].interpolated) ++b;
    const statics::CurvePoint &lo = grown.curve[a], &hi = grown.curve[b];
    EXPECT_GT(p.load, lo.load);
    EXPECT_LT(p.load, hi.load);
    EXPECT_GE(p.eps2, std::min(lo.eps2, hi.eps2));
    EXPECT_LE(p.eps2, std::max(lo.eps2, hi.eps2));
  }
  EXPECT_GT(interpolated, 100);
  EXPECT_EQ(static_cast<std::size_t>(grown.steps + 1 + interpolated), grown.curve.size());
}

TEST(StepGrowth, RefusesAGrowthBelowOne) {
  statics::Q1Options o;
  o.step_growth = 0;
  EXPECT_THROW(statics::find_q1(sample(), o), std::invalid_argument);
}

}  // namespace
