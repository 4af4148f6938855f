// `granstab q1` end to end on a shipped sample: outputs, fields, and the stress/strain options.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "run_granstab.hpp"

namespace {

namespace fs = std::filesystem;
using granstab::testing::quoted;
using granstab::testing::slurp;

class Q1Command : public ::testing::Test {
 protected:
  // `granstab q1 ARGS`: the exit code; its streams in last_.
  int run(const std::string& args) {
    last_ = dir_.run("q1 " + args);
    return last_.exit_code;
  }
  granstab::testing::Workdir dir_{"q1"};
  const fs::path& root_ = dir_.path();
  granstab::testing::CommandResult last_{-1, "", ""};
};

const std::string sample =
    (fs::path(GRANSTAB_SAMPLES_DIR) / "tiny-triangular-periodic.granstab").string();

TEST_F(Q1Command, WritesCurveSummaryAndMode) {
  const fs::path out = root_ / "out";
  ASSERT_EQ(run(quoted(sample) + " --dq 0.5 --out " + quoted(out.string())), 0) << last_.err;
  const std::string json = slurp(out / "q1.json");
  for (const char* field : {"\"q1\":", "\"q1_bracket\":", "\"criterion\": \"existence\"",
                            "\"q_max_rigid\": 27.856", "\"n_disks\": 16", "\"n_contacts\": 48",
                            "\"wall_seconds\":", "\"granstab_version\": \"", "\"blas\": \"/"})
    EXPECT_NE(json.find(field), std::string::npos) << field << "\n" << json;
  // The lattice's mechanism: at q1 its 32 loaded contacts (F_N = 11.45) are on the cone. The 16
  // others carry F_N ~ 1e-9, 1e-10 of those, so whether they count as sliding too is round-off
  // (48 until a step's start residual was taken off its dropped rows, 32 since). Before the step
  // floor settled floppy rotations, the run stopped 6e-7 earlier on "predictor: singular" at
  // 24.5507612 (docs/validation.md); the limit point is 24.5507618-24.5507620.
  const auto number = [&](const std::string& key) {
    const std::size_t at = json.find("\"" + key + "\": ");
    return at == std::string::npos ? -1.0 : std::stod(json.substr(at + key.size() + 4));
  };
  EXPECT_GE(number("n_sliding_at_q1"), 32.0) << json;
  EXPECT_GT(number("q1"), 24.5507616) << json;
  EXPECT_LT(number("q1"), 24.5507621) << json;
  const std::string csv = slurp(out / "static_curve.csv");
  EXPECT_EQ(csv.rfind("step,load,q,epsilon_1,epsilon_2,epsilon_v,n_sliding,hill,", 0), 0u);
  EXPECT_GT(std::count(csv.begin(), csv.end(), '\n'), 40);
  EXPECT_NE(slurp(out / "unstable_mode.csv").find("disk,x,y,ux,uy,theta"), std::string::npos);
  EXPECT_EQ(last_.out.rfind("q1 = ", 0), 0u);
}

TEST_F(Q1Command, StrainControlRuns) {
  const fs::path out = root_ / "strain";
  ASSERT_EQ(run(quoted(sample) + " --control strain --dq 1e-3 --max-steps 5 --out " +
                quoted(out.string())),
            0)
      << last_.err;
  EXPECT_NE(slurp(out / "q1.json").find("\"control\": \"strain\""), std::string::npos);
}

TEST_F(Q1Command, RejectsBadInput) {
  EXPECT_NE(run(quoted((root_ / "missing.granstab").string())), 0);
  EXPECT_NE(last_.err.find("missing.granstab"), std::string::npos);
  EXPECT_NE(run(quoted(sample) + " --control sideways"), 0);
  EXPECT_NE(run(quoted(sample) + " --dq -1"), 0);
}

}  // namespace
