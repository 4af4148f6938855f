#include "static/network.hpp"

namespace granstab::statics {

Network network_from_configuration(const Configuration& config) {
  Network net;
  net.boundary = config.cell.boundary;
  net.length = config.cell.length;
  net.x = config.disks.x;
  net.y = config.disks.y;
  net.radius = config.disks.radius;
  net.theta = config.disks.theta;
  net.contacts = config.contacts;
  net.material = config.material;
  net.loading.sigma = config.stage.sigma_ext;
  net.loading.measure = config.stage.measure;
  net.loading.nominal_length = config.stage.reference_length;
  DofOptions options;
  options.active.assign(config.disks.size(), 1);
  for (int a = 0; a < 2; ++a) {
    net.constraints.cell_free[a] = config.stage.control[a] != LengthControl::fixed;
    options.cell[a] = net.constraints.cell_free[a];
  }
  options.pinned_translation = net.boundary == Boundary::periodic && !net.x.empty() ? 0 : -1;
  net.dofs = build_dof_map(options);
  return net;
}

}  // namespace granstab::statics
