#pragma once
// The frozen contact network of the rigid-limit bound (SPEC §4.5, STATIC.md §S3.6): the frames of
// all contacts and which contacts and disks enter the LP, with the dependent rows removed
// (disks that carry no force, translations of wall-free periodic components, gear torques).
// Internal to static/rigid_*.cpp.
#include <vector>

#include "common/configuration.hpp"
#include "common/contact_law.hpp"
#include "static/rigid_limit.hpp"

namespace granstab::statics::rigid {

struct FrozenNetwork {
  std::vector<ContactFrame> frame;   // per contact of config.contacts
  std::vector<double> mu;            // friction of each contact (mu or mu_wall)
  std::vector<char> active;          // contact enters the LP
  std::vector<char> disk_active;     // disk has balance rows
  std::vector<char> pinned;          // disk whose force rows are dropped (translation of a
                                     // wall-free periodic component: those rows are dependent)
  std::vector<char> torque_dropped;  // disk whose torque row is dependent (a gear mode)
};

// Throws std::invalid_argument for a configuration the LP cannot take (indices, walls, options).
void check_configuration(const Configuration& config, const RigidLimitOptions& options);

FrozenNetwork build_network(const Configuration& config);

}  // namespace granstab::statics::rigid
