// What protocols, checkpoints and the static solver read from an Engine: the stresses of the
// last force pass, energies, the contact count, and the state exported as a Configuration.
#include <cstddef>

#include "common/cell.hpp"
#include "common/contact_law.hpp"
#include "engine.hpp"

namespace granstab {

Engine::Tensor Engine::stress() const {
  const double area = cell_.length[0] * cell_.length[1];
  return {{{sums_.sigma[0] / area, sums_.sigma[1] / area},
           {sums_.sigma[2] / area, sums_.sigma[3] / area}}};
}

std::array<double, 2> Engine::viscous_stress() const {
  const double area = cell_.length[0] * cell_.length[1];
  return {sums_.sigma_viscous[0] / area, sums_.sigma_viscous[1] / area};
}

double Engine::controlled_stress(int axis) const {
  check_axis(axis);
  const double s = stress()[axis][axis];
  if (stage_.measure == StressMeasure::cauchy) return s;
  const int b = 1 - axis;
  return s * cell_.length[b] / stage_.reference_length[b];
}

double Engine::wall_stress(int axis) const {
  check_axis(axis);
  if (cell_.periodic()) return stress()[axis][axis];
  return sums_.wall_force[axis] / cell_.length[1 - axis];
}

double Engine::kinetic_energy() const {
  double e = 0.0;
  for (std::size_t i = 0; i < disks_.size(); ++i) {
    e += disks_.mass[i] * (disks_.vx[i] * disks_.vx[i] + disks_.vy[i] * disks_.vy[i]) +
         disks_.inertia[i] * disks_.omega[i] * disks_.omega[i];
  }
  return 0.5 * e;
}

double Engine::elastic_energy() const {
  double e = 0.0;
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    if (!(pairs_.f_n[p] > 0.0)) continue;
    e += pairs_.f_n[p] * pairs_.f_n[p] / material_.k_n +
         material_.k_t * pairs_.delta_t[p] * pairs_.delta_t[p];
  }
  if (!cell_.periodic()) {
    const Cell c = cell_.cell();
    const Wall walls[4] = {wall_left, wall_right, wall_bottom, wall_top};
    for (std::size_t i = 0; i < disks_.size(); ++i) {
      for (int w = 0; w < 4; ++w) {
        const ContactFrame f =
            disk_wall_frame(disks_.x[i], disks_.y[i], disks_.radius[i], walls[w], c);
        if (f.h > 0.0) {
          e += material_.k_n * f.h * f.h +
               material_.k_t * disks_.wall_delta_t[w][i] * disks_.wall_delta_t[w][i];
        }
      }
    }
  }
  return 0.5 * e;
}

double Engine::cell_kinetic_energy() const {
  return 0.5 * (cell_.mass[0] * cell_.length_rate[0] * cell_.length_rate[0] +
                cell_.mass[1] * cell_.length_rate[1] * cell_.length_rate[1]);
}

std::size_t Engine::contact_count() const {
  std::size_t count = 0;
  for (std::size_t p = 0; p < pairs_.size(); ++p) count += pairs_.f_n[p] > 0.0;
  if (!cell_.periodic()) {
    const Cell c = cell_.cell();
    const Wall walls[4] = {wall_left, wall_right, wall_bottom, wall_top};
    for (std::size_t i = 0; i < disks_.size(); ++i) {
      for (int w = 0; w < 4; ++w) {
        count += disk_wall_frame(disks_.x[i], disks_.y[i], disks_.radius[i], walls[w], c).h > 0.0;
      }
    }
  }
  return count;
}

Configuration Engine::configuration() const {
  Configuration out;
  export_to(out);
  return out;
}

void Engine::export_to(Configuration& out) const {
  const std::size_t n = disks_.size();
  out.disks.x.assign(disks_.x.begin(), disks_.x.begin() + n);
  out.disks.y.assign(disks_.y.begin(), disks_.y.begin() + n);
  out.disks.radius.assign(disks_.radius.begin(), disks_.radius.begin() + n);
  out.disks.mass.assign(disks_.mass.begin(), disks_.mass.end());
  out.disks.inertia.assign(disks_.inertia.begin(), disks_.inertia.end());
  out.disks.vx.assign(disks_.vx.begin(), disks_.vx.begin() + n);
  out.disks.vy.assign(disks_.vy.begin(), disks_.vy.begin() + n);
  out.disks.omega.assign(disks_.omega.begin(), disks_.omega.begin() + n);
  out.disks.theta.assign(disks_.theta.begin(), disks_.theta.end());
  out.cell = cell_.cell();
  out.material = material_;
  out.stage = stage_;
  out.time = time_;
  out.step = step_;
  out.rng_state = rng_state_;

  out.contacts.clear();
  const auto status = [](double f_t, double f_n, double mu) {
    if (!is_sliding(f_t, f_n, mu)) return ContactStatus::stick;
    return f_t > 0.0 ? ContactStatus::slide_positive : ContactStatus::slide_negative;
  };
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    if (!(pairs_.f_n[p] > 0.0)) continue;
    const int i = pairs_.i[p], j = pairs_.j[p];
    int k1 = 0, k2 = 0;
    if (cell_.periodic()) {
      k1 = minimum_image_shift(disks_.x[j] - disks_.x[i], cell_.length[0]);
      k2 = minimum_image_shift(disks_.y[j] - disks_.y[i], cell_.length[1]);
    }
    out.contacts.add(i, j, k1, k2, pairs_.delta_t[p],
                     status(-material_.k_t * pairs_.delta_t[p], pairs_.f_n[p], material_.mu));
  }
  if (!cell_.periodic()) {
    const Cell c = cell_.cell();
    const Wall walls[4] = {wall_left, wall_right, wall_bottom, wall_top};
    for (std::size_t i = 0; i < n; ++i) {
      for (int w = 0; w < 4; ++w) {
        const ContactFrame f =
            disk_wall_frame(disks_.x[i], disks_.y[i], disks_.radius[i], walls[w], c);
        if (!(f.h > 0.0)) continue;
        const double dt = disks_.wall_delta_t[w][i];
        out.contacts.add(static_cast<int>(i), walls[w], 0, 0, dt,
                         status(-material_.k_t * dt, material_.k_n * f.h, material_.mu_wall));
      }
    }
  }
}

}  // namespace granstab
