#include "record.hpp"

namespace granstab::protocols {

std::vector<std::string> state_columns() {
  return {"step",
          "time",
          "L1",
          "L2",
          "dL1_dt",
          "dL2_dt",
          "epsilon_1",
          "epsilon_2",
          "epsilon_v",
          "sigma_11",
          "sigma_22",
          "sigma_12",
          "q",
          "phi",
          "z",
          "x0",
          "x_s",
          "e_c",
          "f_2",
          "torque_2",
          "max_net_force",
          "max_net_torque",
          "contacts",
          "sliding",
          "rattlers",
          "wall_sigma_1",
          "wall_sigma_2"};
}

std::vector<double> state_row(const Configuration& s, const Measurements& m) {
  double wall_1 = m.sigma[0][0], wall_2 = m.sigma[1][1];
  if (!s.cell.periodic()) {
    const auto f = wall_forces(s, contact_loads(s));
    wall_1 = f[1] / s.cell.length[1];
    wall_2 = f[3] / s.cell.length[0];
  }
  return {static_cast<double>(s.step),
          s.time,
          s.cell.length[0],
          s.cell.length[1],
          s.cell.length_rate[0],
          s.cell.length_rate[1],
          m.epsilon_1,
          m.epsilon_2,
          m.epsilon_v,
          m.sigma[0][0],
          m.sigma[1][1],
          m.sigma[0][1],
          m.q,
          m.phi,
          m.z,
          m.x0,
          m.x_s,
          m.e_c,
          m.f_2,
          m.torque_2,
          m.max_net_force,
          m.max_net_torque,
          static_cast<double>(m.n_contacts_carrying),
          static_cast<double>(m.n_sliding),
          static_cast<double>(m.n_rattlers),
          wall_1,
          wall_2};
}

}  // namespace granstab::protocols
