// The hybrid SIC (drivers/hybrid_sic.hpp, issue #24) on the shipped N = 100 sample: its first
// interval is the static run itself, the hand-overs lose nothing, each rearrangement starts at
// the last stable state and ends at the next increment, and the pure dynamic route is the
// compare run's dynamic half, bit for bit.
#include "hybrid_sic.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "common/io/configuration_file.hpp"
#include "common/measurements.hpp"
#include "crosscheck.hpp"
#include "dynamic/protocols/checkpoint.hpp"
#include "dynamic/protocols/equilibration.hpp"
#include "stability_probe.hpp"

namespace {

using namespace granstab;
using hybrid::Method;

const std::filesystem::path sample_path =
    std::filesystem::path(GRANSTAB_SOURCE_DIR) / "data" / "samples" / "periodic-n100-k1e4.granstab";

// The sample at its own mu (0.15): to epsilon_2 = 0.004 the hybrid meets three rearrangements
// (at q = 0.29, 0.34 and 0.38, dq = 1e-2), each a few hundredths of q after the last.
hybrid::SicOptions options() {
  hybrid::SicOptions o;
  o.dq = 1e-2;
  o.epsilon_2_end = 0.004;
  o.statics.hill_every = 0;
  return o;
}

Configuration start() {
  const Configuration sample = read_configuration(sample_path);
  return crosscheck::biaxial_start(sample, sample.material.mu);
}

struct HybridRun : ::testing::Test {
  static void SetUpTestSuite() { run = new hybrid::SicResult(hybrid::run_sic(start(), options())); }
  static void TearDownTestSuite() { delete run; }
  static hybrid::SicResult* run;
};
hybrid::SicResult* HybridRun::run = nullptr;

TEST_F(HybridRun, FirstIntervalIsTheStaticRunItself) {
  statics::Q1Options q1 = options().statics;
  q1.dq = options().dq;
  const statics::StabilityResult s = statics::find_q1(start(), q1);
  ASSERT_NE(s.criterion, statics::Criterion::none);
  ASSERT_GT(run->curve.size(), s.curve.size());
  for (std::size_t k = 0; k < s.curve.size(); ++k) {
    const hybrid::SicPoint& p = run->curve[k];
    EXPECT_EQ(p.method, Method::static_stepping) << k;
    EXPECT_EQ(p.interval, 0);
    EXPECT_EQ(p.q_target, s.curve[k].load) << k;  // same bits: the same run
    EXPECT_EQ(p.eps2, s.curve[k].eps2) << k;
  }
  EXPECT_EQ(run->intervals.at(0).q_end, s.q1);
  EXPECT_EQ(run->curve[s.curve.size()].method, Method::dynamics);
}

TEST_F(HybridRun, RearrangementsGoFromTheLastStableStateToTheNextIncrement) {
  const hybrid::SicOptions o = options();
  EXPECT_EQ(run->stop_reason, "epsilon_2_end");
  ASSERT_GE(run->rearrangements.size(), 2u);
  ASSERT_EQ(run->intervals.size(), run->rearrangements.size());
  double md_steps = 0.0;
  for (std::size_t k = 0; k < run->rearrangements.size(); ++k) {
    const hybrid::Rearrangement& j = run->rearrangements[k];
    const hybrid::StabilityInterval& iv = run->intervals[k];
    EXPECT_TRUE(j.reached) << k;
    EXPECT_EQ(j.q_from, iv.q_end) << k;
    EXPECT_EQ(j.eps2_before, iv.eps2_end) << k;
    // The next multiple of dq strictly above the last stable q.
    EXPECT_GT(j.q_to, j.q_from) << k;
    EXPECT_LE(j.q_to - j.q_from, o.dq * (1.0 + 1e-9)) << k;
    EXPECT_NEAR(j.q_to / o.dq, std::round(j.q_to / o.dq), 1e-9) << k;
    // Past the loss of stability the sample is softer than anywhere in the interval before:
    // d eps2 / dq of the MD increment exceeds the interval's mean.
    const double soft = (j.eps2_after - j.eps2_before) / (j.q_to - j.q_from);
    const double stiff = (iv.eps2_end - iv.eps2_start) / (iv.q_end - iv.q_start);
    EXPECT_GT(soft, stiff) << k;
    // The engine starts from the last stable static state and ends at the recorded equilibrium.
    EXPECT_NEAR(measure(j.before).epsilon_2, j.eps2_before, 1e-12) << k;
    EXPECT_EQ(measure(j.after).epsilon_2, j.eps2_after) << k;
    EXPECT_GT(j.md_steps, 0u);
    md_steps += static_cast<double>(j.md_steps);
    if (k + 1 < run->intervals.size()) {
      EXPECT_EQ(run->intervals[k + 1].q_start, j.q_to);
    }
  }
  EXPECT_EQ(static_cast<double>(run->md_steps), md_steps);
  // The curve: loads never go back; static states of an interval inside it.
  for (std::size_t k = 1; k < run->curve.size(); ++k)
    EXPECT_GE(run->curve[k].q_target, run->curve[k - 1].q_target) << k;
  for (const hybrid::SicPoint& p : run->curve) {
    if (p.method != Method::static_stepping) continue;
    const hybrid::StabilityInterval& iv = run->intervals.at(p.interval);
    EXPECT_GE(p.q_target, iv.q_start);
    EXPECT_LE(p.q_target, iv.q_end);
  }
}

// The MD equilibria are static starts after a polish that moves them no more than the SPEC §3.1
// tolerances allow (the strain uncertainty of crosscheck::static_bound_eps2, from the compliance
// of the interval's own static curve).
TEST_F(HybridRun, StaticStartsFromMdEquilibriaArePolishedWithinTheTolerances) {
  const EquilibriumTolerances tolerances = options().equilibration.tolerances;
  for (std::size_t k = 1; k < run->intervals.size(); ++k) {
    std::vector<statics::CurvePoint> curve;
    for (const hybrid::SicPoint& p : run->curve) {
      if (p.method != Method::static_stepping || p.interval != static_cast<int>(k)) continue;
      statics::CurvePoint c;
      c.load = p.q_target;
      c.eps1 = p.eps1;
      c.eps2 = p.eps2;
      c.epsv = p.epsv;
      curve.push_back(c);
    }
    if (curve.size() < 3) continue;  // no compliance from fewer states
    const double bound =
        crosscheck::static_bound_eps2(curve, run->intervals[k].q_start, 1.0, tolerances);
    EXPECT_GT(run->intervals[k].polish_strain, 0.0) << k;  // an MD state is not exact
    EXPECT_LE(run->intervals[k].polish_strain, bound) << k;
  }
}

// Static -> engine without loss: a stable static state, handed over at its own q, is already in
// SPEC §3.1 equilibrium for the engine (no MD step) and measures the same strains.
TEST(HybridHandOver, StaticStateIsAnEngineEquilibriumAtItsLoad) {
  const Configuration from = start();
  statics::Q1Options q1 = options().statics;
  q1.dq = 1e-2;
  q1.load_stop = 0.1;
  const statics::StabilityResult s = statics::find_q1(from, q1);
  ASSERT_EQ(s.criterion, statics::Criterion::none);
  Configuration state = crosscheck::configuration_of_static_state(s.network_at_q1, from);
  // One rattler, left behind by the strain of its cage, overlaps a neighbour by ~1e-4 a here
  // (a net force of ~1 on that neighbour): the hand-over frees it first.
  const std::vector<char> trapped = crosscheck::overlapping_rattlers(s.network_at_q1, state);
  ASSERT_EQ(std::count(trapped.begin(), trapped.end(), 1), 1);
  EXPECT_EQ(crosscheck::push_out_rattlers(state, trapped), 0);
  EXPECT_EQ(crosscheck::overlapping_rattlers(s.network_at_q1, state), std::vector<char>(100, 0));
  Engine engine(state, EngineOptions{});
  Configuration exported;
  protocols::EquilibrationOptions wait;
  wait.max_steps = 1;
  const auto r = protocols::run_to_equilibrium(engine, wait, exported);
  EXPECT_TRUE(r.reached);
  EXPECT_EQ(r.steps, 0u);
  const Measurements m = measure(exported);
  EXPECT_NEAR(m.epsilon_2, s.curve.back().eps2, 1e-12);
  EXPECT_NEAR(m.q, s.curve.back().q, 1e-9);
}

TEST(HybridSic, PureDynamicRouteIsTheCompareDynamicHalf) {
  hybrid::SicOptions o = options();
  o.hybrid = false;
  o.q_max = 0.05;
  const hybrid::SicResult r = hybrid::run_sic(start(), o);
  crosscheck::CrosscheckOptions c;
  c.dq = o.dq;
  c.equilibration = o.equilibration;
  c.epsilon_2_max = o.epsilon_2_max;
  crosscheck::DynamicRun d;
  crosscheck::run_dynamic(start(), c, o.q_max, d);
  EXPECT_EQ(r.stop_reason, "q_max");
  ASSERT_EQ(r.curve.size(), d.curve.size());
  for (std::size_t k = 0; k < r.curve.size(); ++k) {
    EXPECT_EQ(r.curve[k].method, Method::dynamics);
    EXPECT_EQ(r.curve[k].q_target, d.curve[k].q_target);
    EXPECT_EQ(r.curve[k].eps2, d.curve[k].eps2) << k;
    EXPECT_EQ(r.curve[k].md_steps, d.curve[k].steps) << k;
  }
  EXPECT_TRUE(r.rearrangements.empty());
}

// A restart point through the checkpoint text and back.
hybrid::SicRestart round_trip(const hybrid::SicRestart& r) {
  protocols::Checkpoint c;
  hybrid::put_restart(c, r, 2);
  return hybrid::get_restart(protocols::Checkpoint::parse(c.format(), "test"));
}

void expect_same_curve(const hybrid::SicResult& a, const hybrid::SicResult& b) {
  ASSERT_EQ(a.curve.size(), b.curve.size());
  for (std::size_t k = 0; k < a.curve.size(); ++k) {
    EXPECT_EQ(a.curve[k].method, b.curve[k].method) << k;
    EXPECT_EQ(a.curve[k].q_target, b.curve[k].q_target) << k;
    EXPECT_EQ(a.curve[k].eps2, b.curve[k].eps2) << k;
    EXPECT_EQ(a.curve[k].epsv, b.curve[k].epsv) << k;
    EXPECT_EQ(a.curve[k].md_steps, b.curve[k].md_steps) << k;
  }
  EXPECT_EQ(a.md_steps, b.md_steps);
  EXPECT_EQ(a.static_states, b.static_states);
  EXPECT_EQ(a.stop_reason, b.stop_reason);
  ASSERT_EQ(a.intervals.size(), b.intervals.size());
  for (std::size_t k = 0; k < a.intervals.size(); ++k) {
    EXPECT_EQ(a.intervals[k].q_end, b.intervals[k].q_end) << k;
    EXPECT_EQ(a.intervals[k].end, b.intervals[k].end) << k;
  }
  ASSERT_EQ(a.rearrangements.size(), b.rearrangements.size());
  for (std::size_t k = 0; k < a.rearrangements.size(); ++k)
    EXPECT_EQ(a.rearrangements[k].eps2_after, b.rearrangements[k].eps2_after) << k;
}

// A run continued from any restart point, through the checkpoint text, ends with the bits of the
// uninterrupted run: the hybrid from its second hand-over back to the static stepping, the pure
// dynamic route from its third increment.
TEST(HybridSic, RestartPointsContinueToTheBit) {
  for (const bool hybrid_route : {true, false}) {
    hybrid::SicOptions o = options();
    o.hybrid = hybrid_route;
    if (!hybrid_route) o.q_max = 0.05;
    std::vector<hybrid::SicRestart> points;
    const hybrid::SicResult whole = hybrid::run_sic(
        start(), o, {}, [&](const hybrid::SicRestart& r) { points.push_back(round_trip(r)); });
    ASSERT_GE(points.size(), hybrid_route ? 2u : 3u);
    const hybrid::SicRestart& from = points[hybrid_route ? 1 : 2];
    const hybrid::SicResult resumed = hybrid::run_sic(start(), o, {}, {}, &from);
    expect_same_curve(resumed, whole);
    EXPECT_EQ(resumed.final_state.disks.x, whole.final_state.disks.x);
  }
}

TEST(HybridSic, RefusesBadOptions) {
  hybrid::SicOptions o = options();
  o.dq = 0.0;
  EXPECT_THROW(hybrid::run_sic(start(), o), std::invalid_argument);
  EXPECT_EQ(hybrid::next_increment(0.2832, 0.01), 0.29);
  EXPECT_DOUBLE_EQ(hybrid::next_increment(0.29, 0.01), 0.30);  // strictly above
}

}  // namespace
