// `granstab info` end to end: the built binary on the shipped tiny sample and on a broken file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "run_granstab.hpp"

namespace {

namespace fs = std::filesystem;
using granstab::testing::CommandResult;
using granstab::testing::slurp;

const fs::path samples_dir = GRANSTAB_SAMPLES_DIR;
const fs::path periodic_sample = samples_dir / "tiny-triangular-periodic.granstab";

// Runs granstab in a fresh empty directory, so that anything the command writes there is visible.
class InfoCommand : public ::testing::Test {
 protected:
  CommandResult run(const std::string& args) { return dir_.run(args); }

  granstab::testing::Workdir dir_{"info"};
  const fs::path& root_ = dir_.root();
  const fs::path& work_ = dir_.path();
};

TEST_F(InfoCommand, PrintsTheMeasurementsOfTheTinySample) {
  const CommandResult r = run("info '" + periodic_sample.string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Phi "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("N                16\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("z                6 "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("in equilibrium yes"), std::string::npos) << r.out;
  EXPECT_TRUE(r.err.empty()) << r.err;
}

TEST_F(InfoCommand, PrintsJson) {
  const CommandResult r = run("info --json '" + periodic_sample.string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"phi\": 0.9"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"n_disks\": 16,"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"in_equilibrium\": true"), std::string::npos) << r.out;
}

TEST_F(InfoCommand, TightToleranceFailsTheCheck) {
  const CommandResult r = run("info --force-tolerance 1e-20 '" + periodic_sample.string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;  // info reports; it does not judge
  EXPECT_NE(r.out.find("in equilibrium no"), std::string::npos) << r.out;
}

TEST_F(InfoCommand, MalformedFileIsAnErrorNamingFileAndLine) {
  // Make the first disk's radius negative in a copy of the sample.
  std::istringstream in(slurp(periodic_sample));
  std::ostringstream broken;
  std::string line;
  int number = 0, bad_line = 0;
  bool next_is_disk = false;
  while (std::getline(in, line)) {
    ++number;
    if (next_is_disk && line.front() != '#') {
      std::istringstream fields(line);
      std::string x, y, radius, rest;
      fields >> x >> y >> radius;
      std::getline(fields, rest);
      line = x + " " + y + " -" + radius + rest;
      bad_line = number;
      next_is_disk = false;
    }
    if (line.rfind("disks ", 0) == 0) next_is_disk = true;
    broken << line << "\n";
  }
  ASSERT_GT(bad_line, 0);
  const fs::path file = root_ / "broken.granstab";
  std::ofstream(file) << broken.str();

  const CommandResult r = run("info '" + file.string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("granstab: error: " + file.string() + ":" + std::to_string(bad_line) +
                       ": disk 0: radius must be > 0"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_TRUE(fs::is_empty(work_)) << "info must not write files";
}

TEST_F(InfoCommand, MissingFileIsAnError) {
  const CommandResult r = run("info '" + (root_ / "missing.granstab").string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("missing.granstab: cannot open"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
}

// `granstab version` names the BLAS file that this process loaded (UMFPACK's fronts run on it).
TEST(VersionCommand, NamesTheBlasInUse) {
  granstab::testing::Workdir dir{"version"};
  const CommandResult r = dir.run("version");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const auto at = r.out.find("BLAS: ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string file = r.out.substr(at + 6, r.out.find('\n', at) - at - 6);
  EXPECT_TRUE(fs::exists(file)) << file;
  EXPECT_NE(file.find("blas"), std::string::npos) << file;
}

}  // namespace
