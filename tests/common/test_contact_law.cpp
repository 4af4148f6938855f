// The contact law of SPEC §1.1 in isolation: frames, lever arms, Coulomb return, damping.
#include <gtest/gtest.h>

#include <cmath>

#include "common/contact_law.hpp"
#include "common/material.hpp"

namespace granstab {
namespace {

TEST(ContactLaw, DiskDiskFrameAndLeverArms) {
  const ContactFrame f = disk_disk_frame(0.6, 0.8, 0.5, 0.52);
  EXPECT_DOUBLE_EQ(f.d, 1.0);
  EXPECT_NEAR(f.h, 0.02, 1e-15);
  EXPECT_NEAR(f.a_i + f.a_j, f.d, 1e-15);  // rigid rotation of the pair: no tangential motion
  EXPECT_NEAR(f.nx * f.tx + f.ny * f.ty, 0.0, 1e-15);
  EXPECT_NEAR(f.nx * f.ty - f.ny * f.tx, 1.0, 1e-15);  // t is n turned by +90 degrees
}

TEST(ContactLaw, RigidRotationOfPairGivesNoTangentialRate) {
  const ContactFrame f = disk_disk_frame(0.3, -0.9, 0.45, 0.5);
  const double w = 0.7;  // both disks turn with the pair about i's centre
  const double dvx = -w * f.ly, dvy = w * f.lx;
  EXPECT_NEAR(tangential_rate(f, dvx, dvy, w, w), 0.0, 1e-14);
  EXPECT_NEAR(deflection_rate(f, dvx, dvy), 0.0, 1e-14);
}

TEST(ContactLaw, WallFramePointsIntoWall) {
  Cell cell;
  cell.boundary = Boundary::walls;
  cell.length = {10.0, 20.0};
  const ContactFrame right = disk_wall_frame(9.6, 3.0, 0.5, wall_right, cell);
  EXPECT_DOUBLE_EQ(right.nx, 1.0);
  EXPECT_NEAR(right.h, 0.1, 1e-12);
  const ContactFrame bottom = disk_wall_frame(2.0, 0.45, 0.5, wall_bottom, cell);
  EXPECT_DOUBLE_EQ(bottom.ny, -1.0);
  EXPECT_NEAR(bottom.h, 0.05, 1e-15);
}

TEST(ContactLaw, CoulombReturn) {
  const double k_t = 2.0, mu = 0.5, f_n = 1.0;
  const TangentialForce stick = tangential_force(k_t, mu, f_n, 0.1);
  EXPECT_FALSE(stick.sliding);
  EXPECT_DOUBLE_EQ(stick.f_t, -0.2);
  const TangentialForce slip = tangential_force(k_t, mu, f_n, -0.4);
  EXPECT_TRUE(slip.sliding);
  EXPECT_DOUBLE_EQ(slip.f_t, 0.5);
  EXPECT_DOUBLE_EQ(-k_t * slip.delta_t, slip.f_t);  // stored state reproduces the force
  EXPECT_TRUE(is_sliding(slip.f_t, f_n, mu));
  EXPECT_FALSE(is_sliding(stick.f_t, f_n, mu));
  // An open or tensile contact carries no tangential force.
  EXPECT_DOUBLE_EQ(tangential_force(k_t, mu, 0.0, 0.3).f_t, 0.0);
}

TEST(ContactLaw, ViscousForceIsOutsideCoulombLimit) {
  const ContactForce c = contact_force(100.0, 100.0, 0.5, 3.0, 0.01, 2.0, 0.0, 1.0);
  EXPECT_DOUBLE_EQ(c.f_n, 1.0);
  EXPECT_DOUBLE_EQ(c.f_v, 6.0);
  EXPECT_DOUBLE_EQ(std::abs(c.f_t), 0.5);  // limited by the elastic normal force only
}

TEST(ContactLaw, DampingCoefficient) {
  const Material m = Material::from_kappa(1e4, 0.5, 0.3, 0.8);
  EXPECT_DOUBLE_EQ(m.k_t, 5e3);
  EXPECT_DOUBLE_EQ(m.damping_coefficient(1.0, 1.0), 0.8 * 2.0 * std::sqrt(1e4 * 0.5));
  EXPECT_DOUBLE_EQ(m.damping_coefficient(0.5, INFINITY), 0.8 * 2.0 * std::sqrt(1e4 * 0.5));
}

}  // namespace
}  // namespace granstab
