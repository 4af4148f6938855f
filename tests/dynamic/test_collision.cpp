// Binary collisions (SPEC §1.1): restitution coefficient and contact duration of the linear
// spring-dashpot against the damped linear oscillator, at the default time step.
#include <gtest/gtest.h>

#include <cmath>

#include "helpers.hpp"

namespace granstab {
namespace {

struct Collision {
  double restitution;  // - (relative normal velocity after) / (before)
  double duration;     // time with h > 0 (number of steps with a contact times dt)
  double dt;
  bool separated;
};

constexpr double v0 = 0.1;  // approach speed (the linear law makes e independent of it)

Collision measure(Engine& engine, double v_before, int axis_partner, double max_time) {
  int contact_steps = 0;
  bool separated = false;
  const auto max_steps = static_cast<int>(max_time / engine.dt());
  for (int s = 0; s < max_steps; ++s) {
    engine.step();
    const bool touching = engine.contact_count() > 0;
    contact_steps += touching;
    if (contact_steps > 0 && !touching) {
      separated = true;
      break;
    }
  }
  const double v_after = axis_partner < 0 ? engine.vx()[0] : engine.vx()[1] - engine.vx()[0];
  return {-v_after / v_before, contact_steps * engine.dt(), engine.dt(), separated};
}

// Two disks approach head-on along x in a large periodic cell; the first contact falls a
// fraction `phase` of a step after a step boundary.
Collision disk_disk(double zeta, double r1, double r2, double phase, double max_time = 1.0) {
  const Material m = Material::from_kappa(1e4, 1.0, 0.0, zeta);
  Configuration c = testing::empty_periodic(20.0, 20.0, m);
  c.disks.add(5.0, 10.0, r1);
  c.disks.add(5.0, 10.0, r2);
  const double m1 = c.disks.mass[0], m2 = c.disks.mass[1];
  c.disks.vx[0] = v0 * m2 / (m1 + m2);  // zero total momentum
  c.disks.vx[1] = -v0 * m1 / (m1 + m2);
  const double dt = Engine(c).dt();
  c.disks.x[1] = 5.0 + r1 + r2 + (3.0 + phase) * dt * v0;
  Engine engine(c);
  return measure(engine, -v0, 1, max_time);
}

// One disk hits the (fixed) left wall of a walled box.
Collision disk_wall(double zeta, double phase) {
  Material m = Material::from_kappa(1e4, 1.0, 0.0, zeta);
  Configuration c = testing::empty_periodic(20.0, 20.0, m);
  c.cell.boundary = Boundary::walls;
  c.disks.add(5.0, 10.0, 0.5);
  c.disks.vx[0] = -v0;
  const double dt = Engine(c).dt();
  c.disks.x[0] = 0.5 + (3.0 + phase) * dt * v0;
  Engine engine(c);
  return measure(engine, -v0, -1, 1.0);
}

double expected_restitution(double zeta) {
  return zeta < 1.0 ? std::exp(-M_PI * zeta / std::sqrt(1.0 - zeta * zeta)) : 0.0;
}

// Half period of the damped oscillator of reduced mass m*: the time during which h > 0.
double expected_duration(double zeta, double reduced_mass, double k_n) {
  return M_PI / (std::sqrt(k_n / reduced_mass) * std::sqrt(1.0 - zeta * zeta));
}

TEST(Collision, RestitutionAndDurationMatchDampedOscillator) {
  for (double zeta : {0.0, 0.1, 0.3, 0.5, 0.7, 0.9}) {
    for (double phase : {0.0, 0.37, 0.81}) {
      const Collision c = disk_disk(zeta, 0.5, 0.5, phase);
      ASSERT_TRUE(c.separated);
      EXPECT_NEAR(c.restitution, expected_restitution(zeta), 1e-3)
          << "zeta " << zeta << " phase " << phase;
      // The contact is seen at step boundaries only: the measured duration is within one step.
      EXPECT_NEAR(c.duration, expected_duration(zeta, 0.5, 1e4), 1.01 * c.dt)
          << "zeta " << zeta << " phase " << phase;
    }
  }
}

TEST(Collision, UnequalMasses) {
  // m1 = 1/4, m2 = 1: reduced mass 1/5, and the smallest mass sets dt.
  for (double zeta : {0.2, 0.6}) {
    const Collision c = disk_disk(zeta, 0.25, 0.5, 0.5);
    ASSERT_TRUE(c.separated);
    EXPECT_NEAR(c.restitution, expected_restitution(zeta), 1e-3) << "zeta " << zeta;
    EXPECT_NEAR(c.duration, expected_duration(zeta, 0.2, 1e4), 1.01 * c.dt);
  }
}

TEST(Collision, CriticalDampingNeverBouncesBack) {
  // zeta = 1: the overlap decays to zero without the disks separating (SPEC §1.1); after many
  // undamped periods they still touch and their relative velocity is gone.
  const Collision c = disk_disk(1.0, 0.5, 0.5, 0.3, 2.0);
  EXPECT_FALSE(c.separated);
  EXPECT_NEAR(c.restitution, 0.0, 1e-3);
}

TEST(Collision, WallIsAnInfinitelyHeavyPartner) {
  for (double zeta : {0.0, 0.3, 0.7}) {
    for (double phase : {0.0, 0.5}) {
      const Collision c = disk_wall(zeta, phase);
      ASSERT_TRUE(c.separated);
      EXPECT_NEAR(c.restitution, expected_restitution(zeta), 1e-3)
          << "zeta " << zeta << " phase " << phase;
      EXPECT_NEAR(c.duration, expected_duration(zeta, 1.0, 1e4), 1.01 * c.dt);
    }
  }
}

}  // namespace
}  // namespace granstab
