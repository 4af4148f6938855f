// Per-axis control of a periodic cell (SPEC §1.3): stress control reaches the prescribed
// stresses and its equilibrium does not depend on the cell mass; nominal stress control;
// strain-rate control follows the prescribed L(t).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "helpers.hpp"

namespace granstab {
namespace {

Configuration packing() {
  static const Configuration c =
      testing::dense_packing(64, Material::from_kappa(1e3, 1.0, 0.3, 1.0), 3);
  return c;
}

// Raises sigma_2 from 1 to 1.1 at fixed sigma_1 = 1, in `increments` equal steps `wait` steps
// apart (1 increment: a sudden step), with the cell mass `mass_factor` times the default, and
// returns the equilibrium strains.
std::array<double, 2> load(double mu, double mass_factor, int increments, int wait,
                           Engine** keep = nullptr) {
  Configuration c = packing();
  c.material.mu = mu;
  for (double& m : c.cell.mass) m *= mass_factor;
  auto* e = new Engine(c);
  for (int k = 1; k <= increments; ++k) {
    e->set_sigma_ext(1, 1.0 + 0.1 * k / increments);
    e->run(wait);
  }
  EXPECT_TRUE(testing::run_to_equilibrium(*e, 1e-6, 1e-6, 3000000));
  std::array<double, 2> strain;
  for (int a = 0; a < 2; ++a) strain[a] = 1.0 - e->length()[a] / c.cell.length[a];
  if (keep)
    *keep = e;
  else
    delete e;
  return strain;
}

TEST(StressControl, ReachesPrescribedStresses) {
  Engine* e = nullptr;
  load(0.3, 1.0, 1, 0, &e);
  const auto s = e->stress();
  EXPECT_NEAR(s[0][0], 1.0, 1e-6);
  EXPECT_NEAR(s[1][1], 1.1, 1.1e-6);
  EXPECT_LT(testing::max_net_force_non_rattler(*e), 1e-6);
  delete e;
}

// The equilibrium reached under stress control is a property of the packing, not of the
// cell's inertia, in the quasistatic limit: a slow ramp of the load. (A sudden 10% step on a
// frictional packing is not quasistatic: the overshoot slides contacts, and the final strains
// then depend on the mass by ~25%; measured while writing this test.)
void expect_mass_independent(double mu, int increments, int wait, double rel_tol) {
  const std::array<double, 2> reference = load(mu, 1.0, increments, wait);
  ASSERT_GT(std::abs(reference[1]), 1e-5);  // the load step does deform the sample
  for (double factor : {0.1, 10.0}) {
    const std::array<double, 2> strain = load(mu, factor, increments, wait);
    for (int a = 0; a < 2; ++a) {
      std::printf("mu %.1f, mass x %g: epsilon_%d = %.8e (default mass: %.8e)\n", mu, factor, a + 1,
                  strain[a], reference[a]);
      EXPECT_NEAR(strain[a], reference[a], rel_tol * std::abs(reference[1]))
          << "mass factor " << factor;
    }
  }
}

TEST(StressControl, SlowLoadingIndependentOfCellMass) {
  // Measured: mass x 0.1 changes the strains by 1e-4 of the strain increment, mass x 10 by
  // 3e-3 (the heavier cell follows the ramp less quasistatically).
  expect_mass_independent(0.3, 100, 1000, 1e-2);
}

TEST(StressControl, NominalMeasureUsesReferenceLengths) {
  Configuration c = packing();
  c.stage.measure = StressMeasure::nominal;
  c.stage.reference_length = {c.cell.length[0] * 1.01, c.cell.length[1] * 0.99};
  c.stage.sigma_ext = {1.0, 1.05};
  Engine e(c);
  ASSERT_TRUE(testing::run_to_equilibrium(e, 1e-6, 1e-6, 3000000));
  const auto s = e.stress();
  const auto l = e.length();
  const auto& l0 = c.stage.reference_length;
  // Force across side b = sigma_aa L_b equals sigma_ext_a L_b0.
  EXPECT_NEAR(s[0][0] * l[1] / l0[1], 1.0, 1e-6);
  EXPECT_NEAR(s[1][1] * l[0] / l0[0], 1.05, 1.05e-6);
  EXPECT_NEAR(e.controlled_stress(1), 1.05, 1.05e-6);
}

TEST(StrainRateControl, FollowsPrescribedLength) {
  Configuration c = packing();
  c.material.mu = 0.5;
  Engine e(c);
  const double l20 = e.length()[1], l10 = e.length()[0];
  e.set_reference_lengths_to_current();
  const double rate = 1e-3;  // d epsilon_2 / dt
  e.set_strain_rate_control(1, rate);
  const double t0 = e.time();
  double max_err = 0.0, max_sigma1_err = 0.0;
  for (int k = 0; k < 50; ++k) {
    e.run(400);
    const double expected = l20 * (1.0 - rate * (e.time() - t0));
    max_err = std::max(max_err, std::abs(e.length()[1] - expected) / l20);
    if (k > 10) max_sigma1_err = std::max(max_sigma1_err, std::abs(e.stress()[0][0] - 1.0));
  }
  EXPECT_LT(max_err, 1e-12);  // L2(t) = L20 (1 - rate t) up to round-off
  EXPECT_LT(e.length()[1], l20 * (1.0 - 0.5 * rate * (e.time() - t0)));
  EXPECT_NE(e.length()[0], l10);     // axis 1 is free to move under stress control
  EXPECT_GT(e.stress()[1][1], 1.0);  // compressing along 2 raises sigma_2
  EXPECT_LT(max_sigma1_err, 0.1);    // sigma_1 stays near P (dynamic, gamma ~ 1e-3)
  std::printf(
      "strain-rate control: max |L2 - L2(t)| / L20 = %.2e, max |sigma_1 - 1| = %.3f, "
      "q = %.4f at epsilon_2 = %.4f\n",
      max_err, max_sigma1_err, e.stress()[1][1] / e.stress()[0][0] - 1.0,
      1.0 - e.length()[1] / l20);
}

TEST(FixedControl, LengthsDoNotMove) {
  Configuration c = packing();
  c.stage.control = {LengthControl::fixed, LengthControl::fixed};
  c.stage.sigma_ext = {5.0, 5.0};  // ignored by fixed axes
  Engine e(c);
  e.run(2000);
  EXPECT_EQ(e.length()[0], c.cell.length[0]);
  EXPECT_EQ(e.length()[1], c.cell.length[1]);
}

}  // namespace
}  // namespace granstab
