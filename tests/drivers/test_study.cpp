// granstab study (issue #20): the plan a study file expands to, the refusal of bad files with the
// key named, and a 2 x 2 study killed with SIGKILL and resumed to the same results as one run
// through. The aggregation is tested against a hand computation in scripts/study/
// (test_study_report.py); the MPI path in test_study_mpi.sh when MPI is built.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <thread>

#include "../reliability/child_process.hpp"
#include "run_granstab.hpp"
#include "study_plan.hpp"
#include "study_runner.hpp"

namespace fs = std::filesystem;
using granstab::testing::slurp;
using granstab::testing::spit;
using granstab::testing::Workdir;

namespace {

const std::string prepare_settings = R"(
[sample]
n = 40
boundary = "periodic"
seed = 7
[material]
kappa = 1e4
mu = 0.15
[checkpoint]
every_steps = 2000
)";

const std::string two_by_two = R"(
[study]
out = "out"
[grid]
n = [40, 60]
seed = [1, 2]
[[step]]
command = "prepare"
settings = "prepare.toml"
set = { "sample.n" = "{n}", "sample.seed" = "{seed}" }
[[step]]
command = "q1"
arguments = ["{prepare}/sample.granstab", "--mu", "0.5", "--no-hill", "--quiet"]
)";

// A study file in its own directory; returns its path.
fs::path write_study(const Workdir& dir, const std::string& text) {
  spit(dir / "prepare.toml", prepare_settings);
  spit(dir / "study.toml", text);
  return dir / "study.toml";
}

std::string error_of(const Workdir& dir, const std::string& text) {
  try {
    granstab::study::read_plan(write_study(dir, text));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(accepted)";
}

}  // namespace

TEST(StudyPlan, OneTaskPerStepAndDistinctValuesOfItsKeys) {
  Workdir dir("study-plan");
  auto text = two_by_two;
  text.replace(text.find("seed = [1, 2]"), 13, "seed = [1, 2]\nmu = [0.25, 0.5]");
  text.replace(text.find("\"--mu\", \"0.5\""), 13, "\"--mu\", \"{mu}\"");
  text.replace(text.find("settings ="), 0, "vary = [\"seed\", \"n\"]\n");
  const auto plan = granstab::study::read_plan(write_study(dir, text));
  ASSERT_EQ(plan.points.size(), 8u);
  ASSERT_EQ(plan.tasks.size(), 4u + 8u);                 // one prepared sample serves both mu
  const auto& q1 = plan.tasks[plan.points[3].tasks[1]];  // n 40, seed 2, mu 0.5
  EXPECT_EQ(q1.directory, dir.path() / "out" / "q1" / "n-40_seed-2_mu-0.5");
  const auto& prepared = plan.tasks[plan.points[3].tasks[0]];
  EXPECT_EQ(prepared.directory, dir.path() / "out" / "prepare" / "n-40_seed-2");  // grid order
  EXPECT_EQ(q1.depends, std::vector<std::size_t>{plan.points[3].tasks[0]});
  EXPECT_EQ(q1.root, plan.points[3].tasks[0]);
  const std::vector<std::string> argv{
      "q1",        (prepared.directory / "sample.granstab").string(),
      "--mu",      "0.5",
      "--no-hill", "--quiet",
      "--out",     "."};
  EXPECT_EQ(q1.argv, argv);
  EXPECT_EQ(prepared.argv[1], (dir / "prepare.toml").string());
  EXPECT_NE(std::find(prepared.argv.begin(), prepared.argv.end(), "sample.seed=2"),
            prepared.argv.end());
  EXPECT_EQ(plan.points[2].tasks[0], plan.points[3].tasks[0]);
}

TEST(StudyPlan, BadFilesAreRefusedWithTheKeyNamed) {
  Workdir dir("study-bad");
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = two_by_two;
    t.replace(t.find(from), from.size(), to);
    return error_of(dir, t);
  };
  const std::string file = (dir / "study.toml").string();
  auto expect = [&](const std::string& error, const std::string& part) {
    EXPECT_NE(error.find(file + ":"), std::string::npos) << error;
    EXPECT_NE(error.find(part), std::string::npos) << error;
  };
  expect(with("command = \"q1\"", "command = \"q2\""), "step[2].command: expected one of");
  expect(with("[grid]", "[grids]"), "grids: unknown table");
  expect(with("out = \"out\"", "output = \"out\""), "study.output: unknown key");
  expect(with("n = [40, 60]", "n = [40, \"a/b\"]"), "grid.n: value \"a/b\"");
  expect(with("n = [40, 60]", "n = []"), "grid.n: no values");
  expect(with("seed = [1, 2]", "seed = [1, 1]"), "grid.seed: value 1 given twice");
  expect(with("\"--mu\", \"0.5\"", "\"--mu\", \"{mu}\""), "step[2].arguments: {mu}: neither");
  expect(with("settings = \"prepare.toml\"", "settings = \"missing.toml\""), "step[1].settings: ");
  expect(with("settings = \"prepare.toml\"", ""), "step[1].settings: missing");
  expect(with("\"sample.n\" = \"{n}\"", "\"output.sample\" = \"x\""),
         "step[1].set: output.sample is set by the study");
  expect(with("\"--quiet\"]", "\"--out\", \"x\"]"), "step[2].arguments: --out is set");
  expect(with("command = \"q1\"", "command = \"q1\"\nvary = [\"n\"]"),
         "step[2].vary: must include seed, a key of the first step");
  expect(with("command = \"q1\"", "command = \"q1\"\nvary = [\"m\"]"),
         "step[2].vary: m is not a key of [grid]");
  expect(with("command = \"q1\"", "command = \"q1\"\nrepeat = 2"), "step[2].repeat: unknown key");
  expect(with("command = \"q1\"", "command = \"q1\"\nname = \"prepare\""),
         "step[2].name: \"prepare\" is used");
  expect(with("command = \"prepare\"", "command = \"prepare\"\nvary = [\"n\"]"),
         "step[1].set: {seed}: a grid key not in this step's vary");
  expect(error_of(dir, "[grid]\nn = [1\n"), "study.toml:");
}

// Every result file under out/, without the logs and markers and without the lines that hold
// times or the absolute paths of the work directory.
std::map<std::string, std::string> results(const fs::path& out) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    if (!e.is_regular_file()) continue;
    const std::string name = e.path().filename().string();
    if (name.ends_with(".log") || name.starts_with(".") || name == "study.json") continue;
    std::string kept;
    std::istringstream in(slurp(e.path()));
    for (std::string line; std::getline(in, line);)
      if (line.find("seconds") == std::string::npos &&
          line.find(out.string()) == std::string::npos &&
          line.find("\"settings\"") == std::string::npos)
        kept += line + "\n";
    files[fs::relative(e.path(), out).string()] = kept;
  }
  return files;
}

TEST(Study, KilledAndRunAgainEndsWithTheResultsOfOneRun) {
  Workdir whole("study-whole"), killed("study-killed");
  write_study(whole, two_by_two);
  write_study(killed, two_by_two);
  const auto r = whole.run("study study.toml --jobs 2 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto expected = results(whole / "out");
  ASSERT_EQ(expected.count("q1/n-60_seed-2/q1.json"), 1u);
  ASSERT_EQ(expected.count("prepare/n-40_seed-1/sample.granstab"), 1u);

  int kills = 0;
  for (const char* marker : {"prepare/n-40_seed-2/.done", "q1/n-40_seed-1/.done"}) {
    granstab::testing::Child study(killed.path(),
                                   {"study", "study.toml", "--jobs", "2", "--quiet"});
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);
    while (!fs::exists(killed / "out" / marker) && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    if (study.signal_if_running(SIGKILL)) ++kills;  // the children get SIGTERM: checkpoints
    study.wait();
  }
  EXPECT_GE(kills, 1);
  const auto again = killed.run("study study.toml --jobs 2");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.err.find("done before"), std::string::npos) << again.err;
  EXPECT_EQ(results(killed / "out"), expected);
  // Finished: nothing left to run, and a changed command line is refused, not silently reused.
  const auto third = killed.run("study study.toml");
  EXPECT_NE(third.err.find("8 done before, 0 run now"), std::string::npos) << third.err;
  std::string changed = two_by_two;
  changed.replace(changed.find("\"0.5\""), 5, "\"0.4\"");
  spit(killed / "study.toml", changed);
  const auto refused = killed.run("study study.toml");
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("done with another command line"), std::string::npos) << refused.err;
  // Nor does a checkpoint of the old command line continue under the new one.
  fs::remove(killed / "out/q1/n-40_seed-1/.done");
  spit(killed / "out/q1/n-40_seed-1/q1.checkpoint", "stands for a checkpoint");
  const auto stale = killed.run("study study.toml --only n=40 --only seed=1");
  EXPECT_EQ(stale.exit_code, 1);
  EXPECT_NE(stale.err.find("its checkpoint is of another command line"), std::string::npos)
      << stale.err;
}

TEST(Study, AFailedTaskBlocksItsPointOnlyAndExitsNonZero) {
  Workdir dir("study-fail");
  std::string text = two_by_two;
  text.replace(text.find("\"0.5\""), 5, "\"-1\"");  // q1 refuses mu = -1
  write_study(dir, text);
  const auto r = dir.run("study study.toml --jobs 2");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("4 failed"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(dir / "out/prepare/n-60_seed-2/.done"));
  EXPECT_TRUE(fs::exists(dir / "out/q1/n-60_seed-2/.failed"));
  EXPECT_NE(slurp(dir / "out/q1/n-60_seed-2/stderr.log").find("--mu"), std::string::npos);
}

TEST(StudyPlan, ASiblingStepWaitsOnlyForTheStepItRefines) {
  Workdir dir("study-sibling");
  std::string text = two_by_two;
  text.replace(text.find("seed = [1, 2]"), 13, "seed = [1, 2]\nmu = [0.25, 0.5]");
  text.replace(text.find("\"--mu\", \"0.5\""), 13, "\"--mu\", \"{mu}\"");
  text.replace(text.find("settings ="), 0, "vary = [\"n\", \"seed\"]\n");
  text += R"(
[[step]]
command = "q1"
name = "q1_fixed"
vary = ["n", "seed"]
arguments = ["{prepare}/sample.granstab", "--mu", "0.3"]
)";
  const auto plan = granstab::study::read_plan(write_study(dir, text));
  ASSERT_EQ(plan.tasks.size(), 4u + 8u + 4u);
  const auto& point = plan.points[1];
  const auto& fixed = plan.tasks[point.tasks[2]];
  EXPECT_EQ(fixed.depends, std::vector<std::size_t>{point.tasks[0]});  // not the mu q1
  EXPECT_EQ(fixed.directory, dir.path() / "out" / "q1_fixed" / "n-40_seed-1");
  const std::string fixed_arguments = "\"{prepare}/sample.granstab\", \"--mu\", \"0.3\"";
  text.replace(text.find(fixed_arguments), fixed_arguments.size(), "\"{q1}/q1.json\"");
  const std::string error = error_of(dir, text);
  EXPECT_NE(error.find("step[3].arguments: {q1}: neither a grid key nor an earlier step whose"),
            std::string::npos)
      << error;
}

TEST(StudyPlan, OnlySelectsThePointsWithTheGivenValues) {
  Workdir dir("study-only");
  const auto plan = granstab::study::read_plan(write_study(dir, two_by_two));
  const auto selected = granstab::study::select_points(plan, {{"n", {"60"}}, {"seed", {"1", "2"}}});
  std::size_t n = 0;
  for (std::size_t t = 0; t < plan.tasks.size(); ++t)
    if (selected[t]) {
      ++n;
      EXPECT_NE(plan.tasks[t].directory.string().find("n-60"), std::string::npos);
    }
  EXPECT_EQ(n, 4u);
  EXPECT_THROW(granstab::study::select_points(plan, {{"m", {"1"}}}), std::invalid_argument);
  EXPECT_THROW(granstab::study::select_points(plan, {{"n", {"50"}}}), std::invalid_argument);
}
