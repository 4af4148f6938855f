// The sanity guards and determinism through the built binary (issue #8 items 2 and 4): a run
// with a time step far beyond the stability limit stops with a message naming what blew up,
// where and when, exits non-zero and leaves no garbage output; the same inputs and thread count
// give the same output bits.
#include <gtest/gtest.h>

#include <string>

#include "run_granstab.hpp"
#include "dynamic/protocols/checkpoint.hpp"

namespace granstab {
namespace {

namespace fs = std::filesystem;
using testing::Workdir;

const std::string sample =
    (fs::path(GRANSTAB_SOURCE_DIR) / "data/samples/periodic-n100-k1e4.granstab").string();

TEST(Guards, ATimeStepFarBeyondStabilityStopsWithAMessageAndNoGarbage) {
  Workdir dir("guard-dt");
  testing::spit(dir / "src.toml", "[input]\nsample = \"" + sample + "\"\n" + R"(
[engine]
dt_fraction = 5
[biaxial]
gamma = 1e-3
epsilon_2_max = 0.01
record_interval = 1e-5
[output]
csv = "src.csv"
sample = "final.granstab"
)");
  const auto r = dir.run("biaxial --quiet src.toml");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("biaxial SRC: the run blew up at step "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" disk "), std::string::npos) << r.err;  // names the disk
  EXPECT_NE(r.err.find("is in the checkpoint src.checkpoint"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "final.granstab"));
  EXPECT_FALSE(fs::exists(dir / "src.json"));
  // The CSV holds only rows of checked states (each record is checked first), the checkpoint
  // the last checked safe point before the blow-up; a resume would cut the CSV to its size.
  const std::string csv = testing::slurp(dir / "src.csv");
  EXPECT_FALSE(csv.empty());
  EXPECT_EQ(csv.find("nan"), std::string::npos);
  EXPECT_EQ(csv.find("inf"), std::string::npos);
  const auto checkpoint = protocols::Checkpoint::read(dir / "src.checkpoint");
  EXPECT_LE(checkpoint.count("output.csv.bytes"), csv.size());
  EXPECT_NO_THROW((void)checkpoint.configuration("engine"));  // finite: the reader accepts it
}

TEST(Determinism, TheSameInputsAndThreadCountGiveTheSameBits) {
  Workdir a("determinism-a"), b("determinism-b");
  const std::string settings = "[input]\nsample = \"" + sample + "\"\n" + R"(
[material]
mu = 0.5
[biaxial]
control = "stress-steps"
delta_q = 0.1
q_max = 0.3
[output]
csv = "sic.csv"
sample = "final.granstab"
)";
  testing::spit(a / "sic.toml", settings);
  testing::spit(b / "sic.toml", settings);
  ASSERT_EQ(a.run("biaxial --quiet sic.toml").exit_code, 0);
  ASSERT_EQ(b.run("biaxial --quiet sic.toml").exit_code, 0);
  EXPECT_EQ(testing::slurp(a / "sic.csv"), testing::slurp(b / "sic.csv"));
  EXPECT_EQ(testing::slurp(a / "final.granstab"), testing::slurp(b / "final.granstab"));
}

}  // namespace
}  // namespace granstab
