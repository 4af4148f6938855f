// `granstab compare`, `granstab plot` and `granstab probe` end to end: the JSON fields are present
// and consistent with the CSV files, bad input gives a clear error and no output, the pictures are
// drawn, probe --at-q1 takes the state `granstab q1` stops at.
#include <gtest/gtest.h>

#include <algorithm>
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

// CSV as rows of columns by name.
std::vector<std::map<std::string, double>> read_csv(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  std::vector<std::string> names;
  std::vector<std::map<std::string, double>> rows;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
    if (names.empty()) {
      names = cells;
      continue;
    }
    std::map<std::string, double> row;
    for (std::size_t k = 0; k < cells.size() && k < names.size(); ++k)
      row[names[k]] = std::strtod(cells[k].c_str(), nullptr);
    rows.push_back(row);
  }
  return rows;
}

// One test (ctest runs each test in its own process): the compare run is its set-up.
TEST(CompareCommand, WritesConsistentCurvesAndJsonAndPlotDrawsThem) {
  const Workdir dir("compare");
  const fs::path& root = dir.path();
  const CommandResult result =
      dir.run("compare '" + sample.string() + "' --dq 0.01 --q-max 0.02 --mu 0.5 " +
              "--no-hill --out '" + (root / "out").string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("verdict:"), std::string::npos) << result.out;
  const fs::path out = root / "out";
  const std::string json = slurp(out / "compare.json");
  for (const char* key : {"q1", "dq", "mu", "n_steps_compared", "max_abs_diff_eps2_below_q1",
                          "max_rel_diff_eps2_below_q1", "max_abs_diff_epsv_below_q1",
                          "static_seconds", "dynamic_seconds"})
    EXPECT_FALSE(std::isnan(json_number(json, key))) << key << " in\n" << json;
  for (const char* key : {"\"criterion\": ", "\"dynamic_jump_after_q1\": ", "\"q_max_rigid\": "})
    EXPECT_NE(json.find(key), std::string::npos) << key;
  EXPECT_EQ(json_number(json, "dq"), 0.01);
  EXPECT_EQ(json_number(json, "mu"), 0.5);

  const auto statics = read_csv(out / "static_curve.csv");
  const auto dynamics = read_csv(out / "dynamic_curve.csv");
  const auto matched = read_csv(out / "matched.csv");
  ASSERT_FALSE(statics.empty());
  ASSERT_EQ(dynamics.size(), 3u);
  EXPECT_EQ(json_number(json, "q1"), statics.back().at("load"));  // stopped at q_max, stable
  // Recompute the differences from the two curve files at the same q.
  double max2 = 0.0, maxv = 0.0, maxrel = 0.0;
  int compared = 0;
  for (const auto& d : dynamics) {
    if (d.at("q_target") <= 0.0 || d.at("q_target") > json_number(json, "q1") + 1e-12) continue;
    const auto s = std::find_if(statics.begin(), statics.end(), [&](const auto& row) {
      return std::abs(row.at("load") - d.at("q_target")) < 1e-12;
    });
    ASSERT_NE(s, statics.end()) << "no static state at q = " << d.at("q_target");
    const double d2 = std::abs(d.at("epsilon_2") - s->at("epsilon_2"));
    max2 = std::max(max2, d2);
    maxrel = std::max(maxrel, d2 / std::abs(s->at("epsilon_2")));
    maxv = std::max(maxv, std::abs(d.at("epsilon_v") - s->at("epsilon_v")));
    ++compared;
  }
  EXPECT_EQ(compared, 2);
  EXPECT_EQ(json_number(json, "n_steps_compared"), compared);
  EXPECT_EQ(matched.size(), static_cast<std::size_t>(compared));
  EXPECT_EQ(json_number(json, "max_abs_diff_eps2_below_q1"), max2);
  EXPECT_EQ(json_number(json, "max_abs_diff_epsv_below_q1"), maxv);
  EXPECT_EQ(json_number(json, "max_rel_diff_eps2_below_q1"), maxrel);
  // The picture inputs are there: one disk row per disk; the run stopped at q_max while stable
  // (criterion none), so the mode file holds only its e1, e2 rows.
  EXPECT_NE(json.find("\"criterion\": \"none\""), std::string::npos) << json;
  EXPECT_EQ(read_csv(out / "disks_at_q1.csv").size(), 100u);
  EXPECT_EQ(read_csv(out / "mode.csv").size(), 2u);
  EXPECT_FALSE(read_csv(out / "network_at_q1.csv").empty());

  // granstab plot draws the pictures from these files.
  if (std::system("MPLBACKEND=Agg /usr/bin/python3 -c 'import matplotlib' 2> /dev/null") != 0) {
    GTEST_SKIP() << "/usr/bin/python3 has no matplotlib";
  }
  const CommandResult r = dir.run("plot '" + (root / "out").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"curves", "difference", "sample_at_q1"})
    for (const char* ext : {".png", ".svg"}) {
      const fs::path p = root / "out" / (std::string(name) + ext);
      ASSERT_TRUE(fs::exists(p)) << p;
      EXPECT_GT(fs::file_size(p), 1000u) << p;
    }
}

TEST(CompareCommandErrors, BadInputGivesAClearErrorAndNoOutput) {
  const Workdir dir("compare-bad");
  const fs::path& root = dir.path();
  // A missing sample.
  CommandResult r = dir.run("compare '" + (root / "missing.granstab").string() +
                            "' --dq 0.01 --out '" + (root / "a").string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("missing.granstab"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(root / "a"));
  // A sample under an anisotropic stage is no start for a biaxial test.
  std::string text = slurp(sample);
  const std::size_t at = text.find("stage.sigma_ext 1 1\n");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 20, "stage.sigma_ext 1 1.5\n");
  std::ofstream(root / "aniso.granstab") << text;
  r = dir.run("compare '" + (root / "aniso.granstab").string() + "' --dq 0.01 --out '" +
              (root / "b").string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("sigma_ext"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(root / "b"));
  // A negative step and a negative friction are refused before anything runs.
  r = dir.run("compare '" + sample.string() + "' --dq -1 --out '" + (root / "c").string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_FALSE(fs::exists(root / "c"));
  r = dir.run("compare '" + sample.string() + "' --dq 0.01 --mu -0.2 --out '" +
              (root / "d").string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_FALSE(fs::exists(root / "d"));
  // plot on a directory without compare.json.
  r = dir.run("plot '" + root.string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("compare.json"), std::string::npos) << r.err;
}

// The question `--at-q1` answers (is the state where the static run stopped a stable equilibrium
// of the dynamic module?) needs the very state `granstab q1` stops at: the same adaptive path,
// hence the same q1 bits. At mu 0.5, dq 0.01 fixed steps end 3e-16 lower (0.8147955322265628
// against ...625, the sums of the steps), so a probe that took the fixed path would fail here.
TEST(ProbeCommand, AtQ1ProbesTheStateThatQ1StopsAt) {
  const Workdir dir("probe-at-q1");
  const std::string common = " --mu 0.5 --dq 0.01 --quiet";
  const CommandResult q1 = dir.run("q1 '" + sample.string() + "'" + common + " --hill off --out q");
  ASSERT_EQ(q1.exit_code, 0) << q1.err;
  const double q1_value = json_number(slurp(dir / "q/q1.json"), "q1");

  const CommandResult probe =
      dir.run("probe '" + sample.string() + "'" + common + " --at-q1 --f0 0 --save s --out p");
  ASSERT_EQ(probe.exit_code, 0) << probe.err;
  const auto rows = read_csv(dir / "p/probe.csv");
  ASSERT_EQ(rows.size(), 1u) << slurp(dir / "p/probe.csv");
  EXPECT_EQ(rows[0].at("q"), q1_value);
  int saved = 0;
  for (const auto& entry : fs::directory_iterator(dir / "s"))
    saved += entry.path().filename().string().rfind("static_q_", 0) == 0;
  EXPECT_EQ(saved, 2);  // the state and the state without its overlapping rattlers
}

TEST(ProbeCommand, NothingToProbeIsRefusedWithoutOutput) {
  const Workdir dir("probe-nothing");
  const CommandResult r = dir.run("probe '" + sample.string() + "' --dq 0.01 --out p");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("give --at, --at-q1 or both"), std::string::npos) << r.err;
  EXPECT_TRUE(dir.files().empty());
}

}  // namespace
