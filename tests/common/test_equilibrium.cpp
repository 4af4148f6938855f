// The SPEC §3.1 equilibrium criterion on states whose forces are known.
#include <gtest/gtest.h>

#include "common/equilibrium.hpp"
#include "tiny_samples.hpp"

namespace granstab {
namespace {

TEST(Equilibrium, ClosedFormSamplesAreInEquilibrium) {
  for (const double kappa : {1e3, 1e5}) {
    for (const Configuration& c :
         {samples::triangular_lattice(kappa), samples::square_stack(3, kappa),
          samples::square_stack(5, kappa)}) {
      const EquilibriumReport r = check_equilibrium(c);
      EXPECT_TRUE(r.in_equilibrium);
      // Round-off: the overlap h = R_i + R_j - d ~ 1/kappa comes from a cancellation, so forces
      // and stresses carry relative errors of about 1e-16 * kappa.
      const double round_off = 1e-14 * kappa;
      EXPECT_LT(r.max_net_force, round_off);
      EXPECT_LT(r.max_net_torque, round_off);
      EXPECT_TRUE(r.stress_checked[0] && r.stress_checked[1]);
      EXPECT_LT(r.stress_error[0], round_off) << "kappa " << kappa;
      EXPECT_LT(r.stress_error[1], round_off) << "kappa " << kappa;
    }
  }
}

TEST(Equilibrium, DisplacedDiskBreaksForceBalance) {
  Configuration c = samples::triangular_lattice(1e3);
  c.disks.x[5] += 1e-6;  // force imbalance of order K_N * 1e-6 = 1e-3 > 1e-4
  const EquilibriumReport r = check_equilibrium(c);
  EXPECT_FALSE(r.in_equilibrium);
  EXPECT_FALSE(r.force_ok);
  EXPECT_EQ(r.max_force_disk, 5u);
  EXPECT_GT(r.max_net_force, 1e-4);
  EXPECT_LT(r.max_net_force, 1e-2);
  // A looser tolerance accepts it.
  EquilibriumTolerances loose;
  loose.force = 1e-2;
  EXPECT_TRUE(check_equilibrium(c, loose).force_ok);
}

TEST(Equilibrium, TangentialForcesBreakTorqueBalance) {
  Configuration c = samples::triangular_lattice(1e3);
  c.contacts.delta_t[0] = 1e-6;  // F_T = -1e-3 on one contact: torques ~5e-4 on its disks
  const EquilibriumReport r = check_equilibrium(c);
  EXPECT_FALSE(r.torque_ok);
  EXPECT_NEAR(r.max_net_torque, 1e-3 * (0.5 - 0.5 * samples::triangular_lattice_overlap(1e3)),
              1e-12);
  EXPECT_FALSE(r.in_equilibrium);
}

TEST(Equilibrium, OnlyStressControlledComponentsAreCompared) {
  Configuration c = samples::triangular_lattice(1e3);
  c.stage.sigma_ext = {1.0, 1.001};
  EquilibriumReport r = check_equilibrium(c);
  EXPECT_FALSE(r.stress_ok);
  EXPECT_NEAR(r.stress_error[1], 0.001 / 1.001, 1e-12);
  EXPECT_TRUE(r.force_ok);
  c.stage.control[1] = LengthControl::strain_rate;
  r = check_equilibrium(c);
  EXPECT_TRUE(r.stress_ok);
  EXPECT_FALSE(r.stress_checked[1]);
  EXPECT_TRUE(r.in_equilibrium);
}

TEST(Equilibrium, NominalStressUsesTheReferenceSides) {
  Configuration c = samples::triangular_lattice(1e3);
  c.stage.measure = StressMeasure::nominal;
  // Side L2 was 1% longer at the start of the stage: the force on the x faces over that
  // reference length is sigma_11 / 1.01.
  c.stage.reference_length[1] *= 1.01;
  const EquilibriumReport r = check_equilibrium(c);
  EXPECT_NEAR(r.stress_error[0], 1.0 - 1.0 / 1.01, 1e-12);
  EXPECT_LT(r.stress_error[1], 1e-12);
  EXPECT_FALSE(r.stress_ok);
}

TEST(Equilibrium, RattlersAreExcludedFromTheForceTest) {
  // Two disks pushing each other with F = 50: unbalanced, but both are rattlers.
  Configuration c;
  c.cell.length = {5.0, 4.0};
  c.material = Material::from_kappa(1e3, 1.0, 0.5, 1.0);
  c.disks.add(2.0, 2.0, 0.5);
  c.disks.add(2.95, 2.0, 0.5);
  c.contacts.add(0, 1, 0, 0);
  c.stage.control = {LengthControl::fixed, LengthControl::fixed};
  const EquilibriumReport r = check_equilibrium(c);
  EXPECT_DOUBLE_EQ(r.max_net_force, 0.0);
  EXPECT_TRUE(r.in_equilibrium);
  // Reported beside the criterion.
  c.disks.vx[0] = 2.0;
  EXPECT_DOUBLE_EQ(check_equilibrium(c).e_c, 0.5 * c.disks.mass[0] * 4.0 / 2.0);
}

TEST(Equilibrium, NoContactsUnderStressControlIsNotEquilibrium) {
  Configuration c;
  c.cell.length = {5.0, 5.0};
  c.disks.add(1.0, 1.0, 0.5);
  const EquilibriumReport r = check_equilibrium(c);
  EXPECT_DOUBLE_EQ(r.stress_error[0], 1.0);  // sigma = 0 against sigma_ext = 1
  EXPECT_FALSE(r.in_equilibrium);
}

}  // namespace
}  // namespace granstab
