// The protocol subcommands end to end through the built binary: outputs of a good run, and
// bad settings that must fail with a message naming the field and write nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "common/io/configuration_file.hpp"
#include "run_granstab.hpp"

namespace granstab {
namespace {

using testing::Workdir;

const std::string sample =
    (std::filesystem::path(GRANSTAB_SOURCE_DIR) / "data/samples/periodic-n100-k1e4.granstab")
        .string();

std::size_t lines(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

TEST(BiaxialCommand, StressStepsWriteOneRowPerEquilibriumAndTheSavedStates) {
  Workdir dir("biaxial-sic");
  testing::spit(dir / "sic.toml", "[input]\nsample = \"" + sample + "\"\n" + R"(
[material]
mu = 0.5
[biaxial]
control = "stress-steps"
delta_q = 0.1
q_max = 0.2
[output]
csv = "sic.csv"
sample = "final.granstab"
save_every = 0.2
)");
  const auto r = dir.run("biaxial --quiet sic.toml");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(lines(testing::slurp(dir / "sic.csv")), 4u);  // header + q = 0, 0.1, 0.2
  const std::string summary = testing::slurp(dir / "sic.json");
  EXPECT_NE(summary.find("\"stop_reason\": \"q_max\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"largest_x_s_in_equilibrium\": 0,"), std::string::npos) << summary;
  const Configuration saved = read_configuration(dir / "sic_q_0.200000.granstab");
  EXPECT_NEAR(saved.stage.sigma_ext[1], 1.2, 1e-12);
  EXPECT_EQ(saved.material.mu, 0.5);
  EXPECT_TRUE(std::filesystem::exists(dir / "final.granstab"));
}

TEST(BiaxialCommand, StrainRateWritesRowsAtTheRecordInterval) {
  Workdir dir("biaxial-src");
  testing::spit(dir / "src.toml", "[input]\nsample = \"" + sample + "\"\n" + R"(
[biaxial]
control = "strain-rate"
gamma = 1e-3
epsilon_2_max = 2e-3
record_interval = 5e-4
[output]
csv = "src.csv"
vtk = "snap"
)");
  const auto r = dir.run("biaxial src.toml");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("biaxial SRC: done"), std::string::npos) << r.err;  // progress
  EXPECT_EQ(lines(testing::slurp(dir / "src.csv")), 6u);                   // header + 0 + 4 records
  EXPECT_TRUE(std::filesystem::exists(dir / "snap_final.vtu"));
  EXPECT_NE(testing::slurp(dir / "src.json").find("\"control\": \"strain-rate\""),
            std::string::npos);
}

TEST(CreepCommand, WritesTheCreepStrain) {
  Workdir dir("creep");
  testing::spit(dir / "creep.toml", "[input]\nsample = \"" + sample + "\"\n" + R"(
[material]
mu = 0.5
[creep]
gamma = 1e-3
record_interval = 1e-3
at_epsilon_2 = 2e-3
[output]
csv = "creep.csv"
)");
  const auto r = dir.run("creep --quiet creep.toml");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string summary = testing::slurp(dir / "creep.json");
  EXPECT_NE(summary.find("\"reached_equilibrium\": true"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"delta_epsilon_2\": "), std::string::npos) << summary;
}

TEST(PerturbCommand, OneRowPerDraw) {
  Workdir dir("perturb");
  testing::spit(dir / "perturb.toml", "[input]\nsample = \"" + sample + "\"\n" + R"(
[perturb]
f0 = 1e-2
repetitions = 2
release = false
[output]
csv = "perturb.csv"
)");
  const auto r = dir.run("perturb --quiet perturb.toml");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(lines(testing::slurp(dir / "perturb.csv")), 3u);
  EXPECT_NE(testing::slurp(dir / "perturb.json").find("\"draws_reaching_equilibrium\": 2"),
            std::string::npos);
}

// q = 3 is far beyond what the N = 100 sample holds at mu = 0.5 (its SIC fails near q = 1): the
// held-stress wait must end on the strain guard with a message, not run until the cell collapses.
TEST(PerturbCommand, StrainGuardStopsASampleThatFlows) {
  Workdir dir("perturb-flow");
  testing::spit(dir / "perturb.toml", "[input]\nsample = \"" + sample + "\"\n" + R"(
[material]
mu = 0.5
[perturb]
q = 3
f0 = 1e-3
failure_delta_epsilon_2 = 2e-3
[output]
csv = "perturb.csv"
)");
  const auto r = dir.run("perturb --quiet perturb.toml");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("the strain guard fired"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "perturb.json"));
}

struct BadCase {
  const char* command;
  std::string settings;
  const char* message;  // must appear in the error
};

// gtest prints the case (instead of its bytes) in failure messages and names tests after it.
void PrintTo(const BadCase& c, std::ostream* os) { *os << c.command << ": " << c.message; }

class BadSettings : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadSettings, FailWithAClearErrorAndWriteNothing) {
  const BadCase& c = GetParam();
  Workdir dir("bad-settings");
  testing::spit(dir / "bad.toml", c.settings);
  const auto r = dir.run(std::string(c.command) + " --quiet bad.toml");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bad.toml"), std::string::npos) << "names the file: " << r.err;
  EXPECT_EQ(dir.files(), std::vector<std::string>{"bad.toml"});
}

const std::string input = "[input]\nsample = \"" + sample + "\"\n";
const std::string prepare_ok =
    "[sample]\nn = 20\n[output]\nsample = \"s.granstab\"\ncsv = \"s.csv\"\n";

INSTANTIATE_TEST_SUITE_P(
    Protocols, BadSettings,
    ::testing::Values(
        BadCase{"prepare", prepare_ok + "[compaction]\nstrain_rte = 0.1\n",
                "compaction.strain_rte"},
        BadCase{"prepare", prepare_ok + "[material]\nmu = -0.1\n", "material.mu"},
        BadCase{"prepare", prepare_ok + "[material]\nzeta = 1.5\n", "material.zeta"},
        BadCase{"prepare", prepare_ok + "[material]\nzeta = -0.5\n", "material.zeta"},
        BadCase{"biaxial", input + "[biaxial]\ngamma = -1e-4\n[output]\ncsv = \"x.csv\"\n",
                "biaxial.gamma"},
        BadCase{
            "biaxial",
            input +
                "[biaxial]\ncontrol = \"strain-rate\"\ndelta_q = 0.1\n[output]\ncsv = \"x.csv\"\n",
            "biaxial.delta_q"},
        BadCase{"biaxial", input + "[material]\nmu = -1\n[output]\ncsv = \"x.csv\"\n",
                "material.mu"},
        BadCase{"biaxial", "[input]\nsample = \"missing.granstab\"\n[output]\ncsv = \"x.csv\"\n",
                "input.sample"},
        BadCase{"creep",
                input + "[creep]\nat_q = 0.5\nat_epsilon_2 = 0.01\n[output]\ncsv = \"x.csv\"\n",
                "exactly one of"},
        BadCase{"creep", input + "[creep]\ngamma = 0\nat_q = 0.5\n[output]\ncsv = \"x.csv\"\n",
                "creep.gamma"},
        BadCase{"perturb", input + "[perturb]\nf0 = -1\n[output]\ncsv = \"x.csv\"\n", "perturb.f0"},
        BadCase{"perturb",
                "[input]\nsample = \"nowhere/none.granstab\"\n[output]\ncsv = \"x.csv\"\n",
                "no such file"}),
    [](const ::testing::TestParamInfo<BadCase>& info) {
      return std::string(info.param.command) + std::to_string(info.index);
    });

}  // namespace
}  // namespace granstab
