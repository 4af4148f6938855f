#include "static/dof_map.hpp"

#include <stdexcept>

namespace granstab::statics {

DofMap build_dof_map(const DofOptions& options) {
  const std::size_t n = options.active.size();
  if (!options.rotation_fixed.empty() && options.rotation_fixed.size() != n)
    throw std::invalid_argument("DofOptions.rotation_fixed: size differs from active");
  DofMap map;
  map.ux.assign(n, -1);
  map.uy.assign(n, -1);
  map.theta.assign(n, -1);
  int next = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!options.active[i]) continue;
    if (static_cast<int>(i) != options.pinned_translation) {
      map.ux[i] = next++;
      map.uy[i] = next++;
    }
    if (options.rotation_fixed.empty() || !options.rotation_fixed[i]) map.theta[i] = next++;
  }
  for (int a = 0; a < 2; ++a)
    if (options.cell[a]) map.e[a] = next++;
  map.size = next;
  return map;
}

}  // namespace granstab::statics
