// Issue #6: the cross-check reports the largest dynamic increment below q1 and
// its q, so that a rearrangement of the dynamic run that falls in the last
// increment before the static q1 (and leaves the jump "after q1" ordinary) is
// seen. Hand-made curves.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "drivers/crosscheck.hpp"

namespace granstab::crosscheck {
namespace {

statics::CurvePoint static_state(double load, double eps2) {
  statics::CurvePoint p;
  p.load = load;
  p.q = load;
  p.eps2 = eps2;
  return p;
}

DynamicPoint dynamic_state(double q, double eps2) {
  DynamicPoint p;
  p.q_target = q;
  p.q = q;
  p.eps2 = eps2;
  p.reached = true;
  return p;
}

TEST(DynamicSteps, TheLargestIncrementBelowQ1IsReportedWithItsQ) {
  // Static: eps2 = q up to q1 = 0.45. Dynamic: increments of 0.1, a
  // rearrangement of 0.5 in the increment to q = 0.4 (the last one below q1),
  // an ordinary 0.1 past q1, then 9 at q = 0.6.
  const std::vector<statics::CurvePoint> s{static_state(0.0, 0.0), static_state(0.1, 0.1),
                                           static_state(0.2, 0.2), static_state(0.3, 0.3),
                                           static_state(0.4, 0.4), static_state(0.45, 0.45)};
  const std::vector<DynamicPoint> d{dynamic_state(0.0, 0.0), dynamic_state(0.1, 0.1),
                                    dynamic_state(0.2, 0.2), dynamic_state(0.3, 0.3),
                                    dynamic_state(0.4, 0.8), dynamic_state(0.5, 0.9),
                                    dynamic_state(0.6, 9.9)};
  const Comparison c = compare_curves(s, 0.45, d, 1.0, {});
  EXPECT_NEAR(c.max_dynamic_step_below_q1, 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(c.q_of_max_dynamic_step, 0.4);
  EXPECT_NEAR(c.mean_dynamic_step_below_q1, 0.2, 1e-12);
  // The jump past q1 alone would call this an ordinary crossing.
  EXPECT_NEAR(c.dynamic_jump_after_q1, 0.1, 1e-12);
  // Increments beyond q1 never count, however large.
  EXPECT_LT(c.max_dynamic_step_below_q1, 9.0);
}

TEST(DynamicSteps, NothingBelowQ1GivesNaN) {
  const std::vector<statics::CurvePoint> s{static_state(0.0, 0.0), static_state(0.05, 0.05)};
  const std::vector<DynamicPoint> d{dynamic_state(0.0, 0.0), dynamic_state(0.1, 0.1)};
  const Comparison c = compare_curves(s, 0.05, d, 1.0, {});
  EXPECT_TRUE(std::isnan(c.max_dynamic_step_below_q1));
  EXPECT_TRUE(std::isnan(c.q_of_max_dynamic_step));
}

}  // namespace
}  // namespace granstab::crosscheck
