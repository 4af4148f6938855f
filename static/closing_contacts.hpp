#pragma once
// New contacts that close during a step (STATIC.md §S3.1 events, §S3.2): pairs of force-carrying
// disks, or a disk and a wall, that overlap at dq and are not in the contact list.
#include <vector>

#include <Eigen/Core>

#include "static/network.hpp"

namespace granstab::statics {

struct NewContact {
  int i, j, k1, k2;
};

// Simple search over all pairs of active disks (minimum image in periodic cells). To be replaced
// by the common cell-list pair search once it is committed; O(N^2) is a few tens of ms at 5600.
std::vector<NewContact> closing_contacts(const Network& net, const Eigen::VectorXd& dq);

}  // namespace granstab::statics
