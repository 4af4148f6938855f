// `granstab q1` end to end on a shipped sample: outputs, fields, and the stress/strain options.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string quoted(const std::string& s) {
  std::string q;
  q.reserve(s.size() + 2);
  q.push_back('\'');
  q.append(s);
  q.push_back('\'');
  return q;
}

class Q1Command : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("granstab-q1-" + std::to_string(std::random_device{}()));
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }

  int run(const std::string& args) {
    std::ostringstream command;  // (a stream: GCC 12 warns falsely on long string sums)
    command << '\'' << GRANSTAB_EXE << "' q1 " << args << " > '" << (root_ / "stdout").string()
            << "' 2> '" << (root_ / "stderr").string() << '\'';
    const int status = std::system(command.str().c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  fs::path root_;
};

const std::string sample =
    (fs::path(GRANSTAB_SAMPLES_DIR) / "tiny-triangular-periodic.granstab").string();

TEST_F(Q1Command, WritesCurveSummaryAndMode) {
  const fs::path out = root_ / "out";
  ASSERT_EQ(run(quoted(sample) + " --dq 0.5 --out " + quoted(out.string())), 0)
      << slurp(root_ / "stderr");
  const std::string json = slurp(out / "q1.json");
  for (const char* field : {"\"q1\":", "\"q1_bracket\":", "\"criterion\": \"existence\"",
                            "\"n_sliding_at_q1\": 32", "\"q_max_rigid\": 27.856",
                            "\"n_disks\": 16", "\"n_contacts\": 48", "\"wall_seconds\":"})
    EXPECT_NE(json.find(field), std::string::npos) << field << "\n" << json;
  const std::string csv = slurp(out / "static_curve.csv");
  EXPECT_EQ(csv.rfind("step,load,q,epsilon_1,epsilon_2,epsilon_v,n_sliding,hill,", 0), 0u);
  EXPECT_GT(std::count(csv.begin(), csv.end(), '\n'), 40);
  EXPECT_NE(slurp(out / "unstable_mode.csv").find("disk,x,y,ux,uy,theta"), std::string::npos);
  EXPECT_EQ(slurp(root_ / "stdout").rfind("q1 = ", 0), 0u);
}

TEST_F(Q1Command, StrainControlRuns) {
  const fs::path out = root_ / "strain";
  ASSERT_EQ(run(quoted(sample) + " --control strain --dq 1e-3 --max-steps 5 --out " +
                quoted(out.string())),
            0)
      << slurp(root_ / "stderr");
  EXPECT_NE(slurp(out / "q1.json").find("\"control\": \"strain\""), std::string::npos);
}

TEST_F(Q1Command, RejectsBadInput) {
  EXPECT_NE(run(quoted((root_ / "missing.granstab").string())), 0);
  EXPECT_NE(slurp(root_ / "stderr").find("missing.granstab"), std::string::npos);
  EXPECT_NE(run(quoted(sample) + " --control sideways"), 0);
  EXPECT_NE(run(quoted(sample) + " --dq -1"), 0);
}

}  // namespace
