#pragma once
// What a reader must do with ANY input (issue #8, docs/reliability.md): either accept it or throw
// the documented exception whose message names the place, never crash, hang or throw anything
// else. Shared by the libFuzzer targets (which abort on a violation) and the ctest replay of the
// seed corpus and of every crash ever found (tests/common/test_fuzz_regressions.cpp).
#include <string>
#include <string_view>

namespace granstab::fuzz {

// parse_configuration(input, configuration_source): a rejection must be a std::runtime_error
// "fuzz.granstab:LINE: message" with LINE inside the input; an accepted input must be written
// back by format_configuration and read again to the same text. Returns "" when the contract
// holds, otherwise what went wrong.
inline constexpr std::string_view configuration_source = "fuzz.granstab";
std::string configuration_violation(std::string_view input);

// RunConfig::from_string(input, run_config_source, overrides) read through a schema like a
// protocol's (numbers, integers, a boolean, a choice, a string, paths, then finish()). Every line
// "#set key=value" of the input is also passed as a command-line override, so overrides are
// fuzzed too. A TOML syntax error must be a std::runtime_error "fuzz.toml:LINE:COLUMN: message";
// a setting error a std::invalid_argument naming the source ("fuzz.toml: " or "command line").
inline constexpr std::string_view run_config_source = "fuzz.toml";
std::string run_config_violation(std::string_view input);

// The biaxial material options of q1 / compare / probe (common/material_override.hpp) on a
// two-disk contact carrying a tangential force. Each input line is an option: "mu X",
// "kt_ratio X", "set TEXT" (parse_material_setting) or "clip". A rejection must be a
// std::invalid_argument; an accepted set must give a valid material, keep every contact inside
// its cone and, without clipping, keep the tangential force F_T = -K_T delta_t.
std::string material_options_violation(std::string_view input);

}  // namespace granstab::fuzz
