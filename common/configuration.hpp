#pragma once
// Everything a run needs to continue exactly (issue #2): the unit of exchange between the dynamic
// module, the static module and the file format.
#include <array>
#include <cstdint>
#include <string>

#include "cell.hpp"
#include "contacts.hpp"
#include "disks.hpp"
#include "material.hpp"

namespace granstab {

enum class StressMeasure : std::uint8_t { cauchy, nominal };
// How each cell length (or mobile wall) is driven (SPEC §1.3).
enum class LengthControl : std::uint8_t { stress, strain_rate, fixed };

// The loading stage the configuration belongs to: the reference for strains (SPEC §2) and the
// prescribed stresses, compression positive.
struct Stage {
  std::array<double, 2> reference_length{1.0, 1.0};  // L_a0: epsilon_a = 1 - L_a / L_a0
  std::array<double, 2> sigma_ext{1.0, 1.0};         // prescribed sigma_1, sigma_2 (units of P)
  std::array<LengthControl, 2> control{LengthControl::stress, LengthControl::stress};
  std::array<double, 2> strain_rate{0.0, 0.0};  // d epsilon_a / dt when control is strain_rate
  StressMeasure measure = StressMeasure::cauchy;
};

struct Configuration {
  Disks disks;
  Cell cell;
  Material material;
  Contacts contacts;
  Stage stage;
  double time = 0.0;
  std::uint64_t step = 0;
  std::string rng_state;  // std::mt19937_64 state as written by operator<<; empty if unused
};

}  // namespace granstab
