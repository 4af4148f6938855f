// Creep (SPEC §3.4) and random perturbation (SPEC §3.5) on the shipped small periodic sample.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/equilibrium.hpp"
#include "common/io/configuration_file.hpp"
#include "common/measurements.hpp"
#include "dynamic/protocols/creep.hpp"
#include "dynamic/protocols/perturbation.hpp"
#include "run_granstab.hpp"

namespace granstab {
namespace {

const std::filesystem::path sample_path =
    std::filesystem::path(GRANSTAB_SOURCE_DIR) / "data/samples/periodic-n100-k1e4.granstab";

Engine biaxial_engine() {
  Configuration c = read_configuration(sample_path);
  Engine engine(c);
  Material m = c.material;
  m.mu = 0.5;
  protocols::begin_biaxial_stage(engine, m);
  return engine;
}

TEST(Creep, HoldingTheCurrentQReachesEquilibriumAtThatQ) {
  Engine engine = biaxial_engine();
  protocols::StrainRateOptions src;
  src.gamma = 4e-4;
  src.record_interval = 1e-3;
  Configuration state;
  protocols::run_strain_rate(engine, src, 0.002, 1.0, state, {});
  const double q_hold = protocols::deviator_ratio(engine);
  EXPECT_GT(q_hold, 0.3);  // well into the deviatoric loading
  const protocols::CreepResult creep =
      protocols::hold_deviator(engine, q_hold, 1.0, protocols::CreepOptions{}, state);
  ASSERT_TRUE(creep.equilibrium.reached);
  const EquilibriumReport check = check_equilibrium(state);
  EXPECT_TRUE(check.in_equilibrium);
  ASSERT_TRUE(check.stress_checked[0] && check.stress_checked[1]);  // both axes stress-controlled
  EXPECT_NEAR(state.stage.sigma_ext[1], 1.0 + q_hold, 1e-12);
  EXPECT_NEAR(measure(state).q, q_hold, 3e-4);
  // The strain keeps growing while the sample settles at the held q (the creep strain).
  EXPECT_GT(creep.delta_epsilon_2(), 0.0);
  EXPECT_NEAR(creep.epsilon_2_switch, 0.002, 1e-6);
  EXPECT_EQ(creep.epsilon_2_end, strains(state)[1]);
}

TEST(Perturbation, EveryDrawReachesALoadedAndAReleasedEquilibrium) {
  Engine engine = biaxial_engine();
  engine.set_stress_control(1, 1.3);  // q = 0.3
  Configuration state;
  ASSERT_TRUE(protocols::run_to_equilibrium(engine, {}, state).reached);
  protocols::PerturbationOptions o;
  o.f0 = 1e-2;
  o.repetitions = 2;
  std::mt19937_64 rng(3);
  int records = 0;
  protocols::run_perturbations(
      engine, o, rng, state,
      [&](const Engine&, const Configuration& s, const protocols::PerturbationRecord& r) {
        ++records;
        EXPECT_TRUE(r.loaded.reached);
        EXPECT_TRUE(r.released.reached);
        // Released state: an ordinary equilibrium at q = 0.3 (no external force left).
        EXPECT_TRUE(check_equilibrium(s).in_equilibrium);
        // Small forces, small strains: f0 / (kappa-like stiffness) ~ 1e-6.
        EXPECT_LT(std::abs(r.delta_epsilon_2), 1e-4);
        EXPECT_NE(r.delta_epsilon_2, 0.0);
        return true;
      });
  EXPECT_EQ(records, 2);
}

TEST(Perturbation, LoadedCheckSeesTheExternalForces) {
  // An equilibrium state is not in equilibrium once forces are added to every disk.
  const Configuration c = read_configuration(sample_path);
  std::vector<double> fx(c.disks.size(), 1e-3), fy(c.disks.size(), 0.0);
  EXPECT_TRUE(protocols::check_loaded_equilibrium(c, {}, {}, {}).in_equilibrium);
  const auto loaded = protocols::check_loaded_equilibrium(c, {}, fx, fy);
  EXPECT_FALSE(loaded.in_equilibrium);
  EXPECT_NEAR(loaded.max_net_force, 1e-3, 1e-6);  // the sample's own residual is < 1e-8
}

}  // namespace
}  // namespace granstab
