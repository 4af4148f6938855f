#include "random_gas.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "dynamic/cell_control.hpp"

namespace granstab::protocols {
namespace {

// Buckets of placed disks on a square grid of spacing >= d_max, so that an overlap test looks at
// the 3 x 3 neighbouring buckets only.
class PlacementGrid {
 public:
  PlacementGrid(std::array<double, 2> length, double spacing, bool periodic)
      : length_(length), periodic_(periodic) {
    for (int a = 0; a < 2; ++a) {
      count_[a] = std::max(1, static_cast<int>(std::floor(length[a] / spacing)));
      size_[a] = length[a] / count_[a];
    }
    buckets_.resize(static_cast<std::size_t>(count_[0]) * count_[1]);
  }

  bool free(const Disks& disks, double x, double y, double r) const {
    const int bx = bucket(x, 0), by = bucket(y, 1);
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        int cx = bx + dx, cy = by + dy;
        if (periodic_) {
          cx = (cx + count_[0]) % count_[0];
          cy = (cy + count_[1]) % count_[1];
        } else if (cx < 0 || cy < 0 || cx >= count_[0] || cy >= count_[1]) {
          continue;
        }
        for (const int j : buckets_[index(cx, cy)]) {
          double lx = disks.x[j] - x, ly = disks.y[j] - y;
          if (periodic_) {
            lx -= length_[0] * std::nearbyint(lx / length_[0]);
            ly -= length_[1] * std::nearbyint(ly / length_[1]);
          }
          const double reach = r + disks.radius[j];
          if (lx * lx + ly * ly <= reach * reach) return false;
        }
      }
    }
    return true;
  }

  void insert(int disk, double x, double y) {
    buckets_[index(bucket(x, 0), bucket(y, 1))].push_back(disk);
  }

 private:
  int bucket(double v, int a) const {
    return std::min(count_[a] - 1, std::max(0, static_cast<int>(std::floor(v / size_[a]))));
  }
  std::size_t index(int cx, int cy) const { return static_cast<std::size_t>(cy) * count_[0] + cx; }
  std::array<double, 2> length_;
  bool periodic_;
  std::array<int, 2> count_{};
  std::array<double, 2> size_{};
  std::vector<std::vector<int>> buckets_;
};

}  // namespace

Configuration random_gas(const GasOptions& o, const Material& material, std::mt19937_64& rng) {
  if (o.n < 1) throw std::invalid_argument("random gas: n must be >= 1");
  if (!(o.phi > 0.0 && o.phi < 0.6)) {
    throw std::invalid_argument("random gas: phi must be in (0, 0.6)");
  }
  if (!(o.d_min > 0.0 && o.d_min <= o.d_max)) {
    throw std::invalid_argument("random gas: need 0 < d_min <= d_max");
  }
  std::uniform_real_distribution<double> diameter(o.d_min, o.d_max), unit(0.0, 1.0);
  std::vector<double> radius(static_cast<std::size_t>(o.n));
  double disk_area = 0.0;
  for (double& r : radius) {
    r = 0.5 * diameter(rng);
    disk_area += std::numbers::pi * r * r;
  }
  const double l1 = std::sqrt(disk_area / (o.phi * o.aspect));
  const std::array<double, 2> length{l1, o.aspect * l1};

  Configuration c;
  c.cell.boundary = o.boundary;
  c.cell.length = length;
  c.material = material;
  c.stage.reference_length = length;
  c.stage.control = {LengthControl::stress, LengthControl::stress};
  c.stage.sigma_ext = {1.0, 1.0};
  c.disks.reserve(radius.size());
  const bool periodic = o.boundary == Boundary::periodic;
  PlacementGrid grid(length, o.d_max, periodic);
  constexpr int max_attempts = 1'000'000;
  for (std::size_t i = 0; i < radius.size(); ++i) {
    const double r = radius[i];
    bool placed = false;
    for (int attempt = 0; attempt < max_attempts && !placed; ++attempt) {
      const double x = periodic ? unit(rng) * length[0] : r + unit(rng) * (length[0] - 2 * r);
      const double y = periodic ? unit(rng) * length[1] : r + unit(rng) * (length[1] - 2 * r);
      if (!grid.free(c.disks, x, y, r)) continue;
      grid.insert(static_cast<int>(c.disks.add(x, y, r)), x, y);
      placed = true;
    }
    if (!placed) {
      throw std::runtime_error("random gas: could not place disk " + std::to_string(i) +
                               " without overlap at phi = " + std::to_string(o.phi));
    }
  }
  const double m = dynamic::default_cell_mass(c.disks.mass);
  c.cell.mass = {m, m};
  return c;
}

}  // namespace granstab::protocols
