// `granstab sic --hybrid` and `granstab plot` of its directory end to end: the JSON agrees with
// the curve file, the rearrangement pictures are written, bad input gives a clear error and no
// output.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "run_granstab.hpp"

namespace {

namespace fs = std::filesystem;
using granstab::testing::CommandResult;
using granstab::testing::json_number;
using granstab::testing::slurp;
using granstab::testing::Workdir;

const fs::path sample =
    fs::path(GRANSTAB_SOURCE_DIR) / "data" / "samples" / "periodic-n100-k1e4.granstab";

// The CSV rows as text cells by column name.
std::vector<std::map<std::string, std::string>> read_rows(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  std::vector<std::string> names;
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
    if (names.empty()) {
      names = cells;
      continue;
    }
    std::map<std::string, std::string> row;
    for (std::size_t k = 0; k < cells.size() && k < names.size(); ++k) row[names[k]] = cells[k];
    rows.push_back(row);
  }
  return rows;
}

TEST(SicCommand, HybridWritesAConsistentCurveJsonAndPictures) {
  const Workdir dir("sic");
  const fs::path out = dir.path() / "out";
  const CommandResult r = dir.run("sic '" + sample.string() +
                                  "' --hybrid --dq 0.01 --epsilon-2-end 0.004 --pictures 2 "
                                  "--quiet --out '" +
                                  out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("hybrid SIC: epsilon_2_end"), std::string::npos) << r.out;
  const std::string json = slurp(out / "sic.json");
  const auto rows = read_rows(out / "sic_curve.csv");
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(json_number(json, "states"), static_cast<double>(rows.size()));
  int dynamic = 0, statics = 0;
  for (const auto& row : rows) {
    dynamic += row.at("method") == "dynamic";
    statics += row.at("method") == "static";
  }
  EXPECT_EQ(dynamic + statics, static_cast<int>(rows.size()));
  EXPECT_EQ(json_number(json, "rearrangements"), dynamic);
  EXPECT_GE(dynamic, 2);
  // Every interval after the first starts at an MD state, which the curve lists once.
  EXPECT_EQ(json_number(json, "static_states"),
            statics + json_number(json, "stability_intervals") - 1);
  EXPECT_EQ(json_number(json, "epsilon_2_last"),
            std::strtod(rows.back().at("epsilon_2").c_str(), nullptr));
  EXPECT_GE(json_number(json, "epsilon_2_last"), 0.004);
  EXPECT_NE(json.find("\"method\": \"hybrid\""), std::string::npos);
  std::size_t pictures = 0;
  for (const auto& e : fs::directory_iterator(out))
    pictures += e.path().filename().string().rfind("rearrangement_", 0) == 0;
  EXPECT_EQ(pictures, 8u);  // 2 rearrangements x (before, after) x (disks, network)

  if (std::system("MPLBACKEND=Agg /usr/bin/python3 -c 'import matplotlib' 2> /dev/null") != 0) {
    GTEST_SKIP() << "/usr/bin/python3 has no matplotlib";
  }
  const CommandResult p = dir.run("plot '" + out.string() + "'");
  ASSERT_EQ(p.exit_code, 0) << p.err;
  for (const char* name : {"sic_curve.png", "sic_jumps.svg"}) {
    ASSERT_TRUE(fs::exists(out / name)) << name;
    EXPECT_GT(fs::file_size(out / name), 1000u) << name;
  }
}

// Killed (SIGKILL) once its first checkpoint exists, the same command line continues from it and
// writes the files of an uninterrupted run; other arguments are refused.
TEST(SicCommand, KilledRunContinuesFromItsCheckpoint) {
  const Workdir dir("sic-kill");
  const std::string args = "sic '" + sample.string() +
                           "' --hybrid --dq 0.01 --epsilon-2-end 0.004 --pictures 1 --quiet --out ";
  const CommandResult whole = dir.run(args + "whole");
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  // The run, killed as soon as its first checkpoint exists (a script: the command line quotes).
  const fs::path script = dir.root() / "kill.sh";
  granstab::testing::spit(
      script,
      "cd " + granstab::testing::quoted(dir.path().string()) + "\nOMP_NUM_THREADS=1 " +
          granstab::testing::quoted(granstab::testing::granstab_exe()) + " " + args +
          "part &\npid=$!\nwhile kill -0 $pid 2> /dev/null && [ ! -f part/sic.checkpoint ]; "
          "do sleep 0.002; done\nkill -9 $pid\nwait $pid\nexit 0\n");
  ASSERT_EQ(std::system(("bash " + granstab::testing::quoted(script.string())).c_str()), 0);
  ASSERT_TRUE(fs::exists(dir.path() / "part" / "sic.checkpoint"));
  EXPECT_FALSE(fs::exists(dir.path() / "part" / "sic.json"));
  const CommandResult other = dir.run(
      "sic '" + sample.string() + "' --hybrid --dq 0.02 --epsilon-2-end 0.004 --quiet --out part");
  EXPECT_NE(other.exit_code, 0);
  EXPECT_NE(other.err.find("another run"), std::string::npos) << other.err;
  const CommandResult rest = dir.run(args + "part");
  ASSERT_EQ(rest.exit_code, 0) << rest.err;
  EXPECT_FALSE(fs::exists(dir.path() / "part" / "sic.checkpoint"));
  EXPECT_EQ(slurp(dir.path() / "part" / "sic_curve.csv"),
            slurp(dir.path() / "whole" / "sic_curve.csv"));
  for (const auto& e : fs::directory_iterator(dir.path() / "whole")) {
    const std::string name = e.path().filename().string();
    if (name.rfind("rearrangement_", 0) == 0) {
      EXPECT_EQ(slurp(dir.path() / "part" / name), slurp(e.path())) << name;
    }
  }
  const std::string a = slurp(dir.path() / "part" / "sic.json"),
                    b = slurp(dir.path() / "whole" / "sic.json");
  for (const char* key :
       {"states", "rearrangements", "md_steps", "static_states", "epsilon_2_last"})
    EXPECT_EQ(json_number(a, key), json_number(b, key)) << key;
}

TEST(SicCommand, BadInputGivesAClearErrorAndNoOutput) {
  const Workdir dir("sic-bad");
  const fs::path& root = dir.path();
  CommandResult r = dir.run("sic '" + (root / "missing.granstab").string() + "' --dq 0.01 --out '" +
                            (root / "a").string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("missing.granstab"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(root / "a"));
  r = dir.run("sic '" + sample.string() + "' --dq 0.01 --dq-min 0.1 --out '" +
              (root / "b").string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--dq-min"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(root / "b"));
}

}  // namespace
