// The SIMD kernels (dynamic/contact_forces_simd.cpp, the force pass; integrator_simd.cpp, the
// drift) against the scalar loops: both instantiate the same templates (the contact law,
// drift_disk), so a run must give the same bits with either, with 1 and 2 threads, periodic
// and between walls.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstring>

#include "dynamic/contact_forces.hpp"
#include "helpers.hpp"

namespace granstab {
namespace {

// A violent compaction of 300 disks (5 reduction blocks, pair ranges of every length modulo
// the 4 lanes) with friction and damping: many contacts close, slide and open during a step.
Configuration gas(Boundary boundary) {
  Configuration c =
      testing::random_gas(300, 0.5, Material::from_kappa(1e3, 1.0, 0.3, 0.7), 7, boundary);
  c.stage.control = {LengthControl::stress, LengthControl::stress};
  c.stage.sigma_ext = {1.0, 1.3};
  for (double& m : c.cell.mass) m *= 0.01;
  return c;
}

struct Result {
  Configuration end;
  std::vector<double> fx, fy, torque;
  Engine::Tensor stress;
  std::array<double, 2> viscous_stress;
  std::size_t max_contacts = 0;
};

Result run(const Configuration& start, bool simd, int threads, int steps) {
  const bool was = dynamic::simd_pairs();
  EXPECT_EQ(dynamic::set_simd_pairs(simd), simd);
  omp_set_num_threads(threads);
  EngineOptions options;
  options.parallel_min_disks = 0;  // the team runs these 300 disks
  Engine e(start, options);
  Result r;
  for (int s = 0; s < steps; s += 50) {
    e.run(50);
    r.max_contacts = std::max(r.max_contacts, e.configuration().contacts.size());
  }
  r.end = e.configuration();
  for (std::size_t i = 0; i < e.size(); ++i) {
    r.fx.push_back(e.force_x(i));
    r.fy.push_back(e.force_y(i));
    r.torque.push_back(e.torque(i));
  }
  r.stress = e.stress();
  r.viscous_stress = e.viscous_stress();
  dynamic::set_simd_pairs(was);
  return r;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

template <class T>
bool same_object_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

void expect_identical(const Result& a, const Result& b) {
  EXPECT_TRUE(same_bits(a.end.disks.x, b.end.disks.x));
  EXPECT_TRUE(same_bits(a.end.disks.y, b.end.disks.y));
  EXPECT_TRUE(same_bits(a.end.disks.vx, b.end.disks.vx));
  EXPECT_TRUE(same_bits(a.end.disks.vy, b.end.disks.vy));
  EXPECT_TRUE(same_bits(a.end.disks.omega, b.end.disks.omega));
  EXPECT_TRUE(same_bits(a.end.contacts.delta_t, b.end.contacts.delta_t));
  EXPECT_EQ(a.end.contacts.i, b.end.contacts.i);
  EXPECT_EQ(a.end.contacts.j, b.end.contacts.j);
  EXPECT_TRUE(same_bits(a.fx, b.fx));
  EXPECT_TRUE(same_bits(a.fy, b.fy));
  EXPECT_TRUE(same_bits(a.torque, b.torque));
  EXPECT_TRUE(same_object_bits(a.stress, b.stress));
  EXPECT_TRUE(same_object_bits(a.viscous_stress, b.viscous_stress));
  EXPECT_TRUE(same_object_bits(a.end.cell.length, b.end.cell.length));
}

class SimdPairs : public ::testing::TestWithParam<Boundary> {};

TEST_P(SimdPairs, SameBitsAsScalarLoop) {
  if (!dynamic::set_simd_pairs(true)) {
    GTEST_SKIP() << "no AVX-512 on this CPU (or under valgrind): the kernel never runs";
  }
  const Configuration start = gas(GetParam());
  const int steps = GetParam() == Boundary::walls ? 3000 : 1000;  // walls compact slower
  const Result scalar = run(start, false, 1, steps);
  ASSERT_GT(scalar.max_contacts, 100u) << "too few closed pairs";  // many closed pairs
  for (int threads : {1, 2}) {
    SCOPED_TRACE(threads);
    expect_identical(run(start, true, threads, steps), scalar);
  }
}

INSTANTIATE_TEST_SUITE_P(Boundaries, SimdPairs,
                         ::testing::Values(Boundary::periodic, Boundary::walls),
                         [](const ::testing::TestParamInfo<Boundary>& info) {
                           return info.param == Boundary::periodic ? "periodic" : "walls";
                         });

}  // namespace
}  // namespace granstab
