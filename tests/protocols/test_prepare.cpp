// granstab prepare end to end (issue #4): a tiny periodic and a tiny walled sample reach the
// SPEC §3.1 criterion, and the same seed gives the same bits.
#include <gtest/gtest.h>

#include "common/equilibrium.hpp"
#include "common/io/configuration_file.hpp"
#include "common/measurements.hpp"
#include "run_granstab.hpp"

namespace granstab {
namespace {

using testing::Workdir;

const char* tiny_prepare = R"(
[sample]
n = 40
boundary = "periodic"
seed = 7
[material]
kappa = 1e3
kt_over_kn = 1.0
mu = 0.15
zeta = 1.0
[output]
sample = "tiny.granstab"
csv = "tiny.csv"
record_interval = 2000
)";

TEST(Prepare, ReachesEquilibriumCriterion) {
  Workdir dir("prepare");
  testing::spit(dir / "prepare.toml", tiny_prepare);
  const auto r = dir.run("prepare --quiet prepare.toml");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;  // --quiet
  const Configuration c = read_configuration(dir / "tiny.granstab");
  EXPECT_EQ(c.disks.size(), 40u);
  // The §3.1 check, recomputed from the file by common/equilibrium.hpp.
  const EquilibriumReport report = check_equilibrium(c);
  EXPECT_TRUE(report.in_equilibrium) << report.max_net_force << " " << report.max_net_torque;
  EXPECT_TRUE(report.stress_checked[0] && report.stress_checked[1]);
  const Measurements m = measure(c);
  EXPECT_GT(m.phi, 0.75);  // a jammed packing, far from the gas at 0.2
  EXPECT_LT(m.phi, 0.9);
  EXPECT_GT(m.z, 3.0);
  EXPECT_FALSE(c.rng_state.empty());
  // The next biaxial stage measures strains from here.
  EXPECT_EQ(c.stage.reference_length, c.cell.length);
  const std::string summary = testing::slurp(dir / "tiny.json");
  EXPECT_NE(summary.find("\"reached_equilibrium\": true"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"seed\": 7"), std::string::npos) << summary;
  const std::string csv = testing::slurp(dir / "tiny.csv");
  EXPECT_EQ(csv.rfind("step,time,L1,L2,", 0), 0u) << csv.substr(0, 100);
}

TEST(Prepare, SameSeedSameBitsOtherSeedOtherSample) {
  Workdir dir("prepare-seed");
  testing::spit(dir / "prepare.toml", tiny_prepare);
  ASSERT_EQ(dir.run("prepare --quiet prepare.toml --set output.sample='\"a.granstab\"'").exit_code,
            0);
  ASSERT_EQ(dir.run("prepare --quiet prepare.toml --set output.sample='\"b.granstab\"'").exit_code,
            0);
  ASSERT_EQ(dir.run("prepare --quiet prepare.toml --set sample.seed=8 "
                    "--set output.sample='\"c.granstab\"'")
                .exit_code,
            0);
  const std::string a = testing::slurp(dir / "a.granstab");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, testing::slurp(dir / "b.granstab"));
  EXPECT_NE(a, testing::slurp(dir / "c.granstab"));
}

TEST(Prepare, WalledSampleReachesEquilibriumWithAgreeingWallStress) {
  Workdir dir("prepare-walls");
  testing::spit(dir / "prepare.toml", tiny_prepare);
  const auto r = dir.run(
      "prepare --quiet prepare.toml --set sample.boundary=walls "
      "--set material.mu=0 --set material.kt_over_kn=0.5 "
      "--set compaction.strain_rate=0.01");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Configuration c = read_configuration(dir / "tiny.granstab");
  EXPECT_FALSE(c.cell.periodic());
  EXPECT_TRUE(check_equilibrium(c).in_equilibrium);
  // SPEC §2: with walls, the contact stress and the wall forces per unit length agree.
  const auto loads = contact_loads(c);
  const auto f = wall_forces(c, loads);
  const auto sigma = stress_tensor(c, loads);
  EXPECT_NEAR(f[1] / c.cell.length[1], sigma[0][0], 1e-3);
  EXPECT_NEAR(f[3] / c.cell.length[0], sigma[1][1], 1e-3);
}

}  // namespace
}  // namespace granstab
