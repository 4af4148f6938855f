#pragma once
// New contacts that close during a step (STATIC.md §S3.1 events, §S3.2): pairs of force-carrying
// disks (with with_rattlers: pairs of which at least one is, i.e. also a rattler that an active
// disk closes on), or an active disk and a wall, that overlap at dq and are not in the list.
#include <vector>

#include <Eigen/Core>

#include "static/network.hpp"

namespace granstab::statics {

struct NewContact {
  int i, j, k1, k2;
};

// The common cell-list pair search (all pairs at their minimum image in cells too small for it).
std::vector<NewContact> closing_contacts(const Network& net, const Eigen::VectorXd& dq,
                                         bool with_rattlers = false);

}  // namespace granstab::statics
