#pragma once
// One row of a protocol's CSV time series: every SPEC §2 quantity of a state plus the cell
// lengths (or mobile wall positions) and their rates.
#include <string>
#include <vector>

#include "common/configuration.hpp"
#include "common/measurements.hpp"

namespace granstab::protocols {

std::vector<std::string> state_columns();
// wall_sigma: with walls, the mobile walls' forces over their lengths (SPEC §2's second stress
// measure); in a periodic cell, sigma_11 and sigma_22.
std::vector<double> state_row(const Configuration& state, const Measurements& m);

}  // namespace granstab::protocols
