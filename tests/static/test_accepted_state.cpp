// What an accepted load step leaves behind (docs/static.md §S3.2): a contact that slides at the end
// of the step is on the Coulomb cone at the moved geometry, so that the next check sees it
// critical; the corrector stops at the round-off floor of its residual instead of grinding there.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "common/contact_law.hpp"
#include "common/io/configuration_file.hpp"
#include "static/kinematics.hpp"
#include "static/q1.hpp"

namespace granstab::statics {
namespace {

// periodic-n100 at its own mu = 0.15 (dq = 1e-3) up to q = 0.2, 100 states, 2115 sliding
// contacts in all: before the fix one of them, its |F_T| / (mu F_N) recomputed from the moved
// positions, lay 8.2e-9 below 1 (outside is_sliding's tolerance); now all are at 1 exactly.
TEST(AcceptedState, SlidingContactsStayOnTheCone) {
  const Configuration config = read_configuration(std::filesystem::path(GRANSTAB_SAMPLES_DIR) /
                                                  "periodic-n100-k1e4.granstab");
  Q1Options o;
  o.dq = 1e-3;
  o.hill_every = 0;
  o.load_stop = 0.2;
  int states = 0, sliding = 0, off_cone = 0;
  double worst = 0.0;
  o.on_accepted = [&](double, const Network& net) {
    ++states;
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
    for (std::size_t c = 0; c < net.contacts.size(); ++c) {
      if (!slides(net.contacts.status[c])) continue;
      const ContactState s = evaluate_contact(net, c, zero);
      if (!s.frictional || !(s.f_n > 0.0)) continue;
      ++sliding;
      worst = std::max(worst, std::abs(1.0 - std::abs(s.f_t) / (s.mu * s.f_n)));
      off_cone += !is_sliding(s.f_t, s.f_n, s.mu);
    }
  };
  const StabilityResult r = find_q1(config, o);
  std::printf("%d states, %d sliding contacts, %d off the cone, worst |1 - |F_T| / mu F_N| %.3g\n",
              states, sliding, off_cone, worst);
  ASSERT_EQ(r.criterion, Criterion::none);  // stopped at q = 0.2, below q1 = 0.2834
  EXPECT_GT(sliding, 100);
  EXPECT_EQ(off_cone, 0);
  EXPECT_LT(worst, 1e-12);
}

// Series A (walls, kappa = 1e5) at its biaxial mu = 0.25 up to q = 0.05: the residual's round-off
// floor, eps K_N L / <F_N> ~ 7e-10, lies above the corrector's tolerance 1e-10. Newton used to
// creep along it (5e-10, 4e-10, 3.9e-10, ...) for ~7 iterations per step, each with its line
// search, before the stagnation rule accepted the state; now it stops at the first step that does
// not halve |R| there (206 -> 18 iterations here; to q = 0.3 the same states, epsilon_2 within
// 1.2e-15).
TEST(AcceptedState, TheCorrectorStopsAtItsRoundOffFloor) {
  Configuration config = read_configuration(std::filesystem::path(GRANSTAB_SAMPLES_DIR) /
                                            "series-a-n1024-k1e5-s1.granstab");
  config.material.mu = 0.25;
  Q1Options o;
  o.dq = 1e-3;
  o.hill_every = 0;
  o.load_stop = 0.05;
  const StabilityResult r = find_q1(config, o);
  ASSERT_EQ(r.criterion, Criterion::none);
  int newton = 0, states = 0;
  for (const CurvePoint& p : r.curve)
    if (!p.interpolated && p.load > r.curve.front().load) {
      newton += p.newton_iterations;
      ++states;
    }
  std::printf("%d states, %d Newton iterations (%d in all attempts)\n", states, newton,
              r.timings.newton_iterations);
  ASSERT_GT(states, 10);
  EXPECT_LE(newton, 2 * states);
}

}  // namespace
}  // namespace granstab::statics
