// granstab prepare, compaction.cell_mass_factor (docs/protocols.md): the key is read and
// range-checked, it changes the compaction but not the cell mass written with the sample, the
// default leaves the shipped sample's bits unchanged, and a compaction resumed from any safe point
// (the engine state plus the cursor, as a checkpoint stores them) ends on the same bits.
#include <gtest/gtest.h>

#include <optional>
#include <random>

#include "common/equilibrium.hpp"
#include "common/io/configuration_file.hpp"
#include "dynamic/protocols/compaction.hpp"
#include "dynamic/protocols/random_gas.hpp"
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
[output]
sample = "tiny.granstab"
)";

TEST(PrepareCellMass, BadValuesAreRefusedBeforeAnyOutput) {
  for (const std::string value : {"0", "-1", "2e3", "5e-4", "'\"heavy\"'"}) {
    Workdir dir("prepare-mass-bad");
    testing::spit(dir.root() / "prepare.toml", tiny_prepare);
    const auto r =
        dir.run("prepare --quiet ../prepare.toml --set compaction.cell_mass_factor=" + value +
                " --set output.sample='\"tiny.granstab\"'");
    EXPECT_NE(r.exit_code, 0) << value;
    EXPECT_NE(r.err.find("compaction.cell_mass_factor"), std::string::npos) << r.err;
    EXPECT_TRUE(dir.files().empty()) << value << ": wrote " << dir.files().front();
  }
}

TEST(PrepareCellMass, ScalesTheCompactionAndWritesTheDefaultMass) {
  Workdir dir("prepare-mass");
  testing::spit(dir / "prepare.toml", tiny_prepare);
  ASSERT_EQ(dir.run("prepare --quiet prepare.toml --set output.sample='\"m1.granstab\"'").exit_code,
            0);
  const auto r = dir.run(
      "prepare --quiet prepare.toml --set compaction.cell_mass_factor=10 "
      "--set output.sample='\"m10.granstab\"'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Configuration a = read_configuration(dir / "m1.granstab");
  const Configuration b = read_configuration(dir / "m10.granstab");
  EXPECT_TRUE(check_equilibrium(b).in_equilibrium);
  // A 10x heavier cell falls differently onto the packing: another final state...
  EXPECT_NE(a.cell.length, b.cell.length);
  EXPECT_NE(a.disks.x, b.disks.x);
  // ...written with the default mass, so that a later stage is not affected.
  EXPECT_EQ(a.cell.mass, b.cell.mass);
  const std::string summary = testing::slurp(dir / "m10.json");
  EXPECT_NE(summary.find("\"compaction_cell_mass_factor\": 10"), std::string::npos) << summary;
}

TEST(PrepareCellMass, DefaultRegeneratesTheShippedSampleBitForBit) {
  // data/configs/periodic-n100-k1e4.toml wrote data/samples/periodic-n100-k1e4.granstab; with the
  // key absent or set to 1 the command must write the same bytes (~92 000 steps at N = 100).
  // Both outputs go to the test's directory (the config's own paths point into data/).
  const std::filesystem::path data = std::filesystem::path(GRANSTAB_SOURCE_DIR) / "data";
  const std::string shipped = testing::slurp(data / "samples/periodic-n100-k1e4.granstab");
  ASSERT_FALSE(shipped.empty());
  Workdir dir("prepare-mass-shipped");
  for (const std::string extra : {"", " --set compaction.cell_mass_factor=1"}) {
    const auto r = dir.run(
        "prepare --quiet " + testing::quoted((data / "configs/periodic-n100-k1e4.toml").string()) +
        " --set output.sample='\"" + (dir / "n100.granstab").string() + "\"'" +
        " --set output.summary='\"" + (dir / "n100.json").string() + "\"'" + extra);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(testing::slurp(dir / "n100.granstab") == shipped) << "extra settings:" << extra;
  }
}

TEST(PrepareCellMass, ResumedCompactionEndsOnTheSameBits) {
  const Material material = Material::from_kappa(1e3, 1.0, 0.15, 1.0);
  protocols::GasOptions gas_options;
  gas_options.n = 40;
  std::mt19937_64 rng(7);
  const Configuration gas = protocols::random_gas(gas_options, material, rng);
  protocols::CompactionOptions options;
  options.strain_rate = 0.05;
  options.cell_mass_factor = 10.0;
  Engine uninterrupted_engine(gas);
  Configuration uninterrupted;
  ASSERT_TRUE(
      protocols::compact_isotropically(uninterrupted_engine, options, uninterrupted).reached);
  EXPECT_EQ(uninterrupted.cell.mass, gas.cell.mass);  // the factor acts during the run only
  for (const int phase : {0, 1}) {
    // Keep the state at the 3rd safe point of the phase, as a checkpoint would.
    std::optional<Configuration> saved;
    protocols::Cursor saved_cursor;
    int seen = 0;
    protocols::LoopControl watch;
    watch.hooks.safe_point = [&](const Engine& e, const protocols::Cursor& cursor) {
      if (cursor.phase == phase && !saved && ++seen == 3) {
        saved = e.configuration();
        saved_cursor = cursor;
      }
    };
    Engine engine(gas);
    Configuration ignored;
    protocols::compact_isotropically(engine, options, ignored, {}, watch);
    ASSERT_TRUE(saved) << "phase " << phase;
    EXPECT_EQ(saved->cell.mass[0], 10.0 * gas.cell.mass[0]) << "phase " << phase;
    Engine resumed_engine(*saved);
    protocols::LoopControl resume;
    resume.cursor = saved_cursor;
    resume.resume = true;
    Configuration resumed;
    ASSERT_TRUE(
        protocols::compact_isotropically(resumed_engine, options, resumed, {}, resume).reached);
    EXPECT_EQ(resumed.step, uninterrupted.step) << "phase " << phase;
    EXPECT_EQ(resumed.cell.length, uninterrupted.cell.length) << "phase " << phase;
    EXPECT_EQ(resumed.cell.mass, uninterrupted.cell.mass) << "phase " << phase;
    EXPECT_EQ(resumed.disks.x, uninterrupted.disks.x) << "phase " << phase;
    EXPECT_EQ(resumed.disks.y, uninterrupted.disks.y) << "phase " << phase;
    // A resumed run without the entry masses in its cursor cannot restore them: refused.
    Engine bare_engine(*saved);
    protocols::LoopControl bare = resume;
    bare.cursor.values.clear();
    EXPECT_THROW(protocols::compact_isotropically(bare_engine, options, ignored, {}, bare),
                 std::invalid_argument);
  }
}

}  // namespace
}  // namespace granstab
