// Walls (SPEC §1.3, series A): two fixed walls and two mobile walls with mass under stress
// control; at equilibrium the wall force per unit length equals the contact stress (SPEC §2).
#include <gtest/gtest.h>

#include <cmath>

#include "helpers.hpp"

namespace granstab {
namespace {

TEST(Walls, WallStressEqualsContactStressAtEquilibrium) {
  // Series-A-like: frictionless disks and walls, K_T/K_N = 1/2, zeta near 1.
  const Material m = Material::from_kappa(1e3, 0.5, 0.0, 0.9);
  Configuration c = testing::random_gas(64, 0.2, m, 17, Boundary::walls);
  c.stage.control = {LengthControl::stress, LengthControl::stress};
  c.stage.sigma_ext = {1.0, 1.2};
  Engine e(c);
  ASSERT_TRUE(testing::run_to_equilibrium(e, 1e-6, 1e-6, 3000000));
  const auto sigma = e.stress();
  for (int a = 0; a < 2; ++a) {
    // Force of the disks on the mobile wall / its length = the contact stress sigma_aa (with
    // disk-wall contacts counted with l = d n) = the prescribed stress.
    EXPECT_NEAR(e.wall_stress(a), sigma[a][a], 1e-5 * sigma[a][a]) << "axis " << a;
    EXPECT_NEAR(e.wall_stress(a), c.stage.sigma_ext[a], 1e-5 * sigma[a][a]) << "axis " << a;
  }
  // Every disk stays inside the box.
  for (std::size_t i = 0; i < e.size(); ++i) {
    EXPECT_GT(e.x()[i], 0.0);
    EXPECT_LT(e.x()[i], e.length()[0]);
    EXPECT_GT(e.y()[i], 0.0);
    EXPECT_LT(e.y()[i], e.length()[1]);
  }
  // The exported contact list names the walls.
  const Configuration out = e.configuration();
  int wall_contacts[4] = {0, 0, 0, 0};
  for (std::size_t k = 0; k < out.contacts.size(); ++k) {
    if (is_wall(out.contacts.j[k])) ++wall_contacts[-out.contacts.j[k] - 1];
  }
  for (int w = 0; w < 4; ++w) EXPECT_GT(wall_contacts[w], 0) << "wall " << w;
}

TEST(Walls, StrainRateControlledWallMovesAtImposedVelocity) {
  const Material m = Material::from_kappa(1e3, 0.5, 0.25, 0.9);
  Configuration c = testing::random_gas(64, 0.2, m, 17, Boundary::walls);
  c.stage.control = {LengthControl::stress, LengthControl::stress};
  Engine e(c);
  ASSERT_TRUE(testing::run_to_equilibrium(e, 1e-5, 1e-5, 3000000));
  e.set_reference_lengths_to_current();
  const double l20 = e.length()[1], t0 = e.time();
  e.set_strain_rate_control(1, 1e-3);
  e.run(20000);
  EXPECT_NEAR(e.length()[1], l20 * (1.0 - 1e-3 * (e.time() - t0)), 1e-12 * l20);
  EXPECT_GT(e.wall_stress(1), 1.0);  // pushing the top wall down loads the sample
}

}  // namespace
}  // namespace granstab
