// Physical sanity guards (dynamic/sanity.hpp, issue #8 item 4): a blown-up state is named (what,
// which disk or contact, which step, the value); healthy runs stay far from the limits; the
// RunGuard stops a protocol loop and saves the last sane state.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <vector>

#include "../common/tiny_samples.hpp"
#include "dynamic/protocols/compaction.hpp"
#include "dynamic/protocols/random_gas.hpp"
#include "dynamic/protocols/run_guard.hpp"
#include "dynamic/sanity.hpp"

namespace granstab {
namespace {

std::string blow_up(const Engine& e, const dynamic::SanityLimits& limits = {}) {
  return dynamic::find_blow_up(e, e.configuration(), limits).value_or("sane");
}

TEST(Sanity, TheTinyEquilibriumSamplesAreSane) {
  EXPECT_EQ(blow_up(Engine(samples::square_stack(3, 1e3))), "sane");
  EXPECT_EQ(blow_up(Engine(samples::triangular_lattice(1e3))), "sane");
}

TEST(Sanity, ANanForceInjectedThroughTheApiIsNamedWithDiskAndStep) {
  Engine e(samples::square_stack(3, 1e3));
  std::vector<double> fx(e.size(), 0.0), fy(e.size(), 0.0);
  fx[4] = std::numeric_limits<double>::quiet_NaN();
  e.set_external_forces(fx, fy);
  EXPECT_EQ(blow_up(e), "step 0: disk 4: net force x = nan (not finite)");
  e.step();
  // One step later the NaN has spread through the contacts and the walls: still named.
  const std::string later = blow_up(e);
  EXPECT_EQ(later.substr(0, 8), "step 1: ") << later;
  EXPECT_NE(later.find("(not finite"), std::string::npos) << later;
}

TEST(Sanity, AnOverlapBeyondTheFractionOfTheSmallerRadiusIsNamed) {
  Configuration c = samples::square_stack(3, 1e3);
  c.disks.x[4] += 0.3;  // into disk 5 (radius 0.5): overlap 0.3 + h, about 0.6 r
  c.contacts.clear();
  samples::add_contacts_by_geometry(c);
  Engine e(c);
  const std::string message = blow_up(e);
  EXPECT_NE(message.find("step 0: contact of disk 4 and disk 5: overlap 0.30"), std::string::npos)
      << message;
  EXPECT_NE(message.find("limit sanity.max_overlap_fraction = 0.5"), std::string::npos);
  dynamic::SanityLimits looser;
  looser.max_overlap_fraction = 0.7;
  EXPECT_EQ(blow_up(e, looser), "sane");
}

TEST(Sanity, AnExplodingKineticEnergyIsNamed) {
  Configuration c = samples::square_stack(3, 1e3);
  c.disks.vx[2] = 100.0;  // 0.5 m v^2 = 5000 = 40 K_N r^2 / 2
  Engine e(c);
  EXPECT_NE(blow_up(e).find("step 0: disk 2: kinetic energy 5000 = 40 K_N r^2 / 2"),
            std::string::npos)
      << blow_up(e);
}

TEST(Sanity, TheGuardStopsALoopAndSavesTheLastSaneState) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("granstab-guard-" + std::to_string(std::random_device{}()));
  std::filesystem::create_directories(dir);
  protocols::GuardSettings settings;
  settings.checkpoint = dir / "run.checkpoint";
  settings.every_seconds = 0.0;
  Engine e(samples::square_stack(3, 1e3));
  protocols::RunGuard guard(settings, "test");
  guard.safe_point(e, [&] {
    protocols::Checkpoint c;
    c.set_count("step", e.step_count());
    c.set_configuration("engine", e.configuration());
    return c;
  });
  EXPECT_FALSE(std::filesystem::exists(settings.checkpoint));  // not due: only kept in memory
  std::vector<double> fx(e.size(), 0.0), fy(e.size(), 0.0);
  fy[7] = std::numeric_limits<double>::infinity();
  e.set_external_forces(fx, fy);
  e.run(3);
  try {
    guard.check(e);
    ADD_FAILURE() << "no BlewUp";
  } catch (const protocols::BlewUp& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("test: the run blew up at step 3: "), std::string::npos) << what;
    EXPECT_NE(what.find("(not finite"), std::string::npos) << what;
    EXPECT_NE(what.find("the last sane state (step 0) is in the checkpoint"), std::string::npos)
        << what;
  }
  const auto saved = protocols::Checkpoint::read(settings.checkpoint);
  EXPECT_EQ(saved.count("step"), 0u);
  std::filesystem::remove_all(dir);
}

TEST(Sanity, AProtocolLoopWithGuardHooksStopsOnANanForce) {
  protocols::GuardSettings settings;
  settings.checkpoint = std::filesystem::temp_directory_path() / "granstab-never-written";
  settings.every_seconds = 0.0;
  protocols::RunGuard guard(settings, "loop");
  Engine e(samples::square_stack(3, 1e3));
  std::vector<double> fx(e.size(), 0.0), fy(e.size(), 0.0);
  fx[0] = std::numeric_limits<double>::quiet_NaN();
  e.set_external_forces(fx, fy);
  protocols::LoopControl control;
  control.hooks.check = [&](const Engine& engine) { guard.check(engine); };
  Configuration state;
  EXPECT_THROW(protocols::run_to_equilibrium(e, {}, state, {}, fx, fy, control), protocols::BlewUp);
  EXPECT_FALSE(std::filesystem::exists(settings.checkpoint));  // nothing sane was kept
}

// The margins of healthy runs against the default limits (measured values in
// docs/reliability.md): a kappa = 1e3 compaction from a gas, with the free fall and overshoot.
TEST(Sanity, AHealthyCompactionStaysFarBelowTheDefaultLimits) {
  protocols::GasOptions gas;
  gas.n = 60;
  std::mt19937_64 rng(3);
  Engine e(protocols::random_gas(gas, Material::from_kappa(1e3, 1.0, 0.15, 1.0), rng));
  dynamic::SanityMargins worst;
  const auto observe = [&](const Engine&, const Configuration& s, const EquilibriumReport&) {
    const auto m = dynamic::sanity_margins(s);
    worst.overlap_fraction = std::max(worst.overlap_fraction, m.overlap_fraction);
    worst.kinetic_energy = std::max(worst.kinetic_energy, m.kinetic_energy);
    return true;
  };
  protocols::CompactionOptions options;
  options.equilibration.check_interval = 20;
  Configuration state;
  ASSERT_TRUE(protocols::compact_isotropically(e, options, state, observe).reached);
  const dynamic::SanityLimits defaults;
  std::printf("largest overlap / r = %.3g, largest kinetic energy / (K_N r^2 / 2) = %.3g\n",
              worst.overlap_fraction, worst.kinetic_energy);
  // Measured 0.13 and 0.031 (the overshoot of the free fall): margins of 4 and 30.
  EXPECT_LT(worst.overlap_fraction, 0.5 * defaults.max_overlap_fraction);
  EXPECT_LT(worst.kinetic_energy, 0.1 * defaults.max_kinetic_energy);
}

}  // namespace
}  // namespace granstab
