// Checkpoint and resume end to end (issue #8 items 1 and 2): a run killed by a real SIGKILL at
// several moments and resumed each time ends with outputs identical to the bit to the
// uninterrupted run's; SIGINT / SIGTERM write a final checkpoint and exit with 128 + signal.
//
// The one field that cannot be identical is "wall_seconds" of the JSON summaries (wall-clock
// time, which a resumed run also counts differently); those lines are removed before comparing,
// everything else is compared byte for byte. Hidden temporary files ".NAME.tmp-XXXXXX" that a
// kill in the middle of an atomic write leaves behind are not outputs and are not compared.
#include <gtest/gtest.h>

#include <csignal>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "run_granstab.hpp"

namespace granstab {
namespace {

namespace fs = std::filesystem;
using testing::Child;
using testing::Workdir;

const std::string sample =
    (fs::path(GRANSTAB_SOURCE_DIR) / "data/samples/periodic-n100-k1e4.granstab").string();

// Every output file under dir by relative name, JSON summaries without their wall-clock lines
// ("wall_seconds"; compare's "static_seconds", "dynamic_seconds", "rigid_seconds").
std::map<std::string, std::string> outputs(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string name = e.path().filename().string();
    if (name.starts_with(".") || name.ends_with(".toml")) continue;
    std::string text = testing::slurp(e.path());
    if (name.ends_with(".json")) {
      std::istringstream in(text);
      std::string line, kept;
      while (std::getline(in, line)) {
        if (line.find("_seconds\"") == std::string::npos) kept += line + "\n";
      }
      text = kept;
    }
    files[fs::relative(e.path(), dir).string()] = text;
  }
  return files;
}

struct Scenario {
  std::string command;     // "prepare", "biaxial", ...
  std::string settings;    // TOML text
  std::string checkpoint;  // the checkpoint file the settings name
  // The command line of the first run; default: COMMAND --quiet run.toml.
  std::vector<std::string> arguments = {};
  std::string final_output = "";  // a file only a finished run writes (Signals tests)

  std::vector<std::string> start() const {
    return arguments.empty() ? std::vector<std::string>{command, "--quiet", "run.toml"} : arguments;
  }
};

// Runs the scenario uninterrupted in one directory, and in another killed with SIGKILL after
// each count of new checkpoints in kill_after, resumed after every kill, then to the end.
// Returns the number of kills that happened (a run may end before a late kill point).
int compare_killed_with_uninterrupted(const Scenario& s, const std::vector<int>& kill_after) {
  Workdir reference("resume-ref"), killed("resume-kill");
  testing::spit(reference / "run.toml", s.settings);
  testing::spit(killed / "run.toml", s.settings);
  {
    Child run(reference.path(), s.start());
    EXPECT_EQ(run.wait(), 0) << testing::slurp(reference.path().parent_path() / "stderr.log");
  }
  int kills = 0;
  bool finished = false;
  for (const int k : kill_after) {
    const std::vector<std::string> args =
        kills == 0 ? s.start() : std::vector<std::string>{"resume", "--quiet", s.checkpoint};
    Child run(killed.path(), args);
    if (!run.signal_after(killed / s.checkpoint, k, SIGKILL)) {
      EXPECT_EQ(run.wait(), 0) << testing::slurp(killed.path().parent_path() / "stderr.log");
      finished = true;  // it ended before the k-th checkpoint
      break;
    }
    EXPECT_EQ(run.wait(), 128 + SIGKILL);
    ++kills;
    // A CSV flushed after the last checkpoint (the commands also flush every 30 s) holds rows
    // the checkpoint does not know: simulate one, the resume must cut it away.
    for (const auto& e : fs::directory_iterator(killed.path())) {
      if (e.path().extension() == ".csv") {
        testing::spit(e.path(), testing::slurp(e.path()) + "1,2,3\n");
      }
    }
  }
  if (!finished) {
    Child rest(killed.path(), {"resume", "--quiet", s.checkpoint});
    EXPECT_EQ(rest.wait(), 0) << testing::slurp(killed.path().parent_path() / "stderr.log");
  }
  EXPECT_FALSE(fs::exists(killed / s.checkpoint)) << "a finished run removes its checkpoint";
  // A kill in an atomic write leaves a temporary; the next resume removes it.
  for (const auto& e : fs::recursive_directory_iterator(killed.path())) {
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
  }
  const auto expected = outputs(reference.path()), got = outputs(killed.path());
  EXPECT_EQ(expected.size(), got.size());
  for (const auto& [name, text] : expected) {
    const auto it = got.find(name);
    EXPECT_TRUE(it != got.end()) << name << " missing after the resumed run";
    if (it != got.end()) {
      EXPECT_TRUE(it->second == text) << name << " differs";
    }
  }
  return kills;
}

const std::string prepare_settings = R"(
[sample]
n = 40
boundary = "periodic"
seed = 7
[material]
kappa = 1e3
[output]
sample = "tiny.granstab"
csv = "tiny.csv"
record_interval = 1000
vtk = "snap"
vtk_interval = 3000
[checkpoint]
every_steps = 400
)";

TEST(Resume, PrepareKilledFourTimesEndsIdentical) {
  const int kills = compare_killed_with_uninterrupted(
      {"prepare", prepare_settings, "tiny.checkpoint"}, {2, 5, 3, 6});
  EXPECT_GE(kills, 2);
}

TEST(Resume, PrepareWithStrainRatePhaseKilledEndsIdentical) {
  // Kill points in the strain-rate phase (checkpoints every 300 steps) and in the stress phase.
  const int kills = compare_killed_with_uninterrupted(
      {"prepare", prepare_settings + "[compaction]\nstrain_rate = 0.05\n", "tiny.checkpoint"},
      {1, 4, 10, 10});
  EXPECT_GE(kills, 2);
}

TEST(Resume, BiaxialStrainRateKilledEndsIdentical) {
  const int kills =
      compare_killed_with_uninterrupted({"biaxial", "[input]\nsample = \"" + sample + "\"\n" + R"(
[biaxial]
control = "strain-rate"
gamma = 1e-3
epsilon_2_max = 4e-3
record_interval = 2e-4
[output]
csv = "src.csv"
sample = "final.granstab"
save_every = 1e-3
[checkpoint]
every_steps = 150
)",
                                         "src.checkpoint"},
                                        {2, 3, 5, 4});
  EXPECT_GE(kills, 2);
}

TEST(Resume, BiaxialStressStepsKilledEndsIdentical) {
  const int kills =
      compare_killed_with_uninterrupted({"biaxial", "[input]\nsample = \"" + sample + "\"\n" + R"(
[material]
mu = 0.5
[biaxial]
control = "stress-steps"
delta_q = 0.05
q_max = 0.3
[output]
csv = "sic.csv"
sample = "final.granstab"
save_every = 0.1
[checkpoint]
every_steps = 400
)",
                                         "sic.checkpoint"},
                                        {1, 3, 2, 4});
  EXPECT_GE(kills, 2);
}

TEST(Resume, CreepWithResumedStrainRateKilledEndsIdentical) {
  const int kills = compare_killed_with_uninterrupted(
      {"creep", "[input]\nsample = \"" + sample + "\"\n" + R"(
[material]
mu = 0.5
[creep]
gamma = 1e-3
record_interval = 5e-4
at_epsilon_2 = 2e-3
resume = true
epsilon_2_max = 4e-3
[output]
csv = "creep.csv"
hold_sample = "hold.granstab"
sample = "final.granstab"
[checkpoint]
every_steps = 2000
)",
       "creep.checkpoint"},
      // About 25 checkpoints: 5 in the SRC phase, 17 in the hold, 3 in the resumed SRC.
      {3, 5, 6, 8, 6});
  EXPECT_GE(kills, 2);
}

TEST(Resume, PerturbKilledEndsIdentical) {
  const int kills = compare_killed_with_uninterrupted(
      {"perturb", "[input]\nsample = \"" + sample + "\"\n" + R"(
[perturb]
f0 = 1e-2
repetitions = 2
seed = 3
[output]
csv = "perturb.csv"
sample = "final.granstab"
[checkpoint]
every_steps = 2000
)",
       "perturb.checkpoint"},
      {3, 5, 4, 6});  // about 25 checkpoints: the loaded and released waits of both draws
  EXPECT_GE(kills, 2);
}

// SIGINT and SIGTERM: the handler only sets a flag; the loop writes a checkpoint at its next
// safe point and the command exits with 128 + signal and a message saying how to continue.
void interrupt_and_resume(const Scenario& s, int signal) {
  Workdir reference("signal-ref"), stopped("signal-stop");
  testing::spit(reference / "run.toml", s.settings);
  testing::spit(stopped / "run.toml", s.settings);
  {
    Child run(reference.path(), s.start());
    ASSERT_EQ(run.wait(), 0);
  }
  {
    Child run(stopped.path(), s.start());
    ASSERT_TRUE(run.signal_after(stopped / s.checkpoint, 2, signal)) << "finished too early";
    EXPECT_EQ(run.wait(), 128 + signal);
  }
  const std::string err = testing::slurp(stopped.path().parent_path() / "stderr.log");
  EXPECT_NE(err.find(signal == SIGINT ? "stopped by SIGINT" : "stopped by SIGTERM"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("granstab resume " + s.checkpoint), std::string::npos) << err;
  ASSERT_TRUE(fs::exists(stopped / s.checkpoint));
  EXPECT_FALSE(fs::exists(stopped / s.final_output)) << "no final output from a stopped run";
  {
    Child rest(stopped.path(), {"resume", "--quiet", s.checkpoint});
    ASSERT_EQ(rest.wait(), 0) << testing::slurp(stopped.path().parent_path() / "stderr.log");
  }
  EXPECT_EQ(outputs(reference.path()), outputs(stopped.path()));
}

const Scenario prepare_scenario{
    "prepare", prepare_settings, "tiny.checkpoint", {}, "tiny.granstab"};

TEST(Signals, SigtermWritesACheckpointAndExits143) {
  interrupt_and_resume(prepare_scenario, SIGTERM);
}
TEST(Signals, SigintWritesACheckpointAndExits130) {
  interrupt_and_resume(prepare_scenario, SIGINT);
}

// compare: the dynamic SIC half checkpoints ([checkpoint] settings given with --set); the static
// half is run again by the resume. Two substeps per delta q, so that a checkpoint between two
// recorded states holds the steps since the last record. About 70 checkpoints.
const Scenario compare_scenario{
    "compare",
    "",
    "out/compare.checkpoint",
    {"compare", sample, "--dq", "0.01", "--q-max", "0.03", "--mu", "0.5", "--no-hill",
     "--dynamic-substeps", "2", "--out", "out", "--set", "checkpoint.every_steps=400"},
    "out/compare.json"};

TEST(Resume, CompareKilledEndsIdentical) {
  const int kills = compare_killed_with_uninterrupted(compare_scenario, {2, 9, 17, 25});
  EXPECT_GE(kills, 3);
}

TEST(Signals, CompareSigtermWritesACheckpointAndExits143) {
  interrupt_and_resume(compare_scenario, SIGTERM);
}

TEST(Resume, RefusesADamagedCheckpointAndAChangedInput) {
  Workdir dir("resume-bad");
  testing::spit(dir / "bad.checkpoint", "granstab-checkpoint 1\nrun.command 7\nprepare\nend 1\n");
  auto r = dir.run("resume bad.checkpoint");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bad.checkpoint: checksum mismatch"), std::string::npos) << r.err;
  r = dir.run("resume missing.checkpoint");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("missing.checkpoint"), std::string::npos) << r.err;
  // A biaxial run stopped by SIGTERM, then its input sample changed: resume refuses.
  testing::spit(dir / "in.granstab", testing::slurp(sample));
  testing::spit(dir / "run.toml", R"(
[input]
sample = "in.granstab"
[biaxial]
gamma = 1e-3
epsilon_2_max = 0.02
[output]
csv = "src.csv"
[checkpoint]
every_steps = 100
)");
  {
    Child run(dir.path(), {"biaxial", "--quiet", "run.toml"});
    ASSERT_TRUE(run.signal_after(dir / "src.checkpoint", 1, SIGTERM));
    ASSERT_EQ(run.wait(), 128 + SIGTERM);
  }
  testing::spit(dir / "in.granstab", testing::slurp(sample) + "\n");
  r = dir.run("resume src.checkpoint");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("changed since the run started"), std::string::npos) << r.err;
}

// `granstab resume --set`: the settings that may change in the middle of a run are taken (a
// smaller time step for a run that blew up), the others refused with a message.
double json_value(const std::string& json, const std::string& key) {
  const std::size_t at = json.find("\"" + key + "\": ");
  return at == std::string::npos ? -1.0 : std::strtod(json.c_str() + at + key.size() + 4, nullptr);
}

TEST(Resume, SetChangesOnlyTheSettingsThatMayChangeMidRun) {
  Workdir dir("resume-set"), reference("resume-set-ref");
  const std::string settings = "[input]\nsample = \"" + sample + "\"\n" + R"(
[biaxial]
gamma = 1e-3
epsilon_2_max = 4e-3
[output]
csv = "src.csv"
[checkpoint]
every_steps = 100
)";
  testing::spit(dir / "run.toml", settings);
  testing::spit(reference / "run.toml", settings);
  ASSERT_EQ(reference.run("biaxial --quiet run.toml").exit_code, 0);
  {
    Child run(dir.path(), {"biaxial", "--quiet", "run.toml"});
    ASSERT_TRUE(run.signal_after(dir / "src.checkpoint", 2, SIGTERM));
    ASSERT_EQ(run.wait(), 128 + SIGTERM);
  }
  const std::string before = testing::slurp(dir / "src.checkpoint");
  for (const char* bad :
       {"input.sample=other.granstab", "biaxial.gamma=1e-2", "engine.skin=0.2", "dt_fraction"}) {
    const auto r = dir.run(std::string("resume --quiet --set ") + bad + " src.checkpoint");
    EXPECT_EQ(r.exit_code, 1) << bad;
    EXPECT_NE(r.err.find("resume may change only engine.dt_fraction"), std::string::npos) << r.err;
    EXPECT_EQ(testing::slurp(dir / "src.checkpoint"), before) << "a refused resume runs nothing";
  }
  auto r = dir.run("resume --quiet --set biaxial.gamma=1e-2 src.checkpoint");
  EXPECT_NE(r.err.find("biaxial.gamma cannot change in the middle of a run"), std::string::npos)
      << r.err;
  // Too large a time step: it blows up, and the checkpoint keeps the last sane state.
  r = dir.run("resume --quiet --set engine.dt_fraction=5 src.checkpoint");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("blew up"), std::string::npos) << r.err;
  ASSERT_TRUE(fs::exists(dir / "src.checkpoint"));
  // Retried with half the default step and no more checkpoints: it finishes with that step,
  // and removes the checkpoint it was resumed from although it wrote none.
  r = dir.run(
      "resume --quiet --set engine.dt_fraction=0.025 --set checkpoint.every_steps=0 "
      "--set checkpoint.every_seconds=0 src.checkpoint");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir / "src.checkpoint"));
  const double dt = json_value(testing::slurp(dir / "src.json"), "dt");
  const double dt_reference = json_value(testing::slurp(reference / "src.json"), "dt");
  ASSERT_GT(dt_reference, 0.0);
  EXPECT_DOUBLE_EQ(dt, 0.5 * dt_reference);
}

// A kill during an atomic write leaves ".NAME.tmp-XXXXXX" beside NAME (simulated here by
// creating such files): the next run, or resume, of the same outputs removes those it owns and
// nothing else.
TEST(Resume, StaleTemporariesOfTheOutputsAreRemovedByTheNextRunAndResume) {
  Workdir dir("resume-tmp");
  testing::spit(dir / "run.toml", "[input]\nsample = \"" + sample + "\"\n" + R"(
[biaxial]
gamma = 1e-3
epsilon_2_max = 4e-3
[output]
csv = "src.csv"
save_every = 1e-3
[checkpoint]
every_steps = 100
)");
  const std::vector<std::string> owned{".src.csv.tmp-Ab12Cd", ".src.checkpoint.tmp-x1y2z3",
                                       ".src.json.tmp-QWERTY",
                                       ".src_e2_0.001000.granstab.tmp-a1b2c3"};
  const std::vector<std::string> foreign{".other.csv.tmp-Ab12Cd", ".src.csv.tmp-abc",
                                         ".srcx.csv.tmp-Ab12Cd", "src.csv.tmp-Ab12Cd"};
  const auto plant = [&](const std::vector<std::string>& names) {
    for (const auto& n : names) testing::spit(dir / n, "partial");
  };
  const auto check = [&](const char* when) {
    for (const auto& n : owned) EXPECT_FALSE(fs::exists(dir / n)) << n << " after " << when;
    for (const auto& n : foreign) EXPECT_TRUE(fs::exists(dir / n)) << n << " after " << when;
  };
  plant(owned);
  plant(foreign);
  {
    Child run(dir.path(), {"biaxial", "--quiet", "run.toml"});
    ASSERT_TRUE(run.signal_after(dir / "src.checkpoint", 1, SIGTERM));
    ASSERT_EQ(run.wait(), 128 + SIGTERM);
  }
  check("a new run");
  plant(owned);
  ASSERT_EQ(dir.run("resume --quiet src.checkpoint").exit_code, 0);
  check("a resume");
  // compare: the temporaries of its output directory and checkpoint.
  fs::create_directories(dir / "out");
  const std::vector<std::string> compare_owned{"out/.compare.checkpoint.tmp-x1y2z3",
                                               "out/.dynamic_curve.csv.tmp-Ab12Cd",
                                               "out/.compare.json.tmp-QWERTY"};
  plant(compare_owned);
  const auto r =
      dir.run("compare '" + sample + "' --dq 0.01 --q-max 0.01 --mu 0.5 --no-hill --out out");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const auto& n : compare_owned) EXPECT_FALSE(fs::exists(dir / n)) << n;
}

}  // namespace
}  // namespace granstab
