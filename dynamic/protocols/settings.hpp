#pragma once
// The TOML sections shared by the protocol subcommands (docs/protocols.md), read through
// common/run_config.hpp so that every value is range-checked and unknown keys are errors.
#include <cstdint>
#include <filesystem>
#include <optional>

#include "common/material.hpp"
#include "common/run_config.hpp"
#include "dynamic/engine.hpp"
#include "equilibration.hpp"

namespace granstab::protocols {

// [material] kappa, kt_over_kn, mu, zeta, mu_wall; absent keys keep `fallback`'s values
// (kappa is K_N in units of P = 1).
Material read_material(RunConfig& rc, const Material& fallback);
// [equilibrium] force, torque, stress (SPEC §3.1 defaults 1e-4), check_interval, max_steps.
EquilibrationOptions read_equilibration(RunConfig& rc);
// [engine] dt_fraction, skin.
EngineOptions read_engine_options(RunConfig& rc);
// A required path key: throws std::invalid_argument "SOURCE: key: required" when absent.
std::filesystem::path required_path(RunConfig& rc, std::string_view key);
// An input file that must exist: throws std::invalid_argument naming key and path.
std::filesystem::path existing_file(RunConfig& rc, std::string_view key);

}  // namespace granstab::protocols
