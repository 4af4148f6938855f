#pragma once
// The biaxial stage's material (issue #19): a sample is prepared with one friction (mu_prep) and
// tested with another (SPEC §3.2), and K_T/K_N may be varied on the same sample. q1, compare and
// probe (and the Python module) change the sample's material through this one function.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "configuration.hpp"

namespace granstab {

struct MaterialOverrides {
  // --set material.KEY=VALUE, in the order given (KEY: k_n, k_t, mu, zeta, mu_wall).
  std::vector<std::pair<std::string, double>> set;
  std::optional<double> kt_ratio;  // --kt-ratio: K_T = ratio K_N, applied after --set
  std::optional<double> mu;        // --mu, applied last
  // Contacts whose |F_T| exceeds the new mu F_N (mu_wall for wall contacts) are moved onto the
  // cone instead of refused.
  bool clip_to_cone = false;

  bool empty() const { return set.empty() && !kt_ratio && !mu; }
};

struct MaterialOverrideReport {
  int clipped = 0;  // contacts moved onto the cone (clip_to_cone)
};

// Parses "material.KEY=VALUE" (the --set syntax); throws std::invalid_argument naming the text.
std::pair<std::string, double> parse_material_setting(const std::string& text);

// Applies the overrides to config.material. A change of K_T rescales every contact's tangential
// elastic displacement delta_t by K_T_old / K_T_new, so that the start state's tangential forces
// F_T = -K_T delta_t are unchanged. Then every frictional contact must satisfy |F_T| <= mu F_N:
// otherwise std::invalid_argument names the first offending contact and its disks, unless
// clip_to_cone (then |F_T| is set to mu F_N and the contact marked sliding). Throws
// std::invalid_argument for an unknown key or an invalid material (validate(Material)).
MaterialOverrideReport apply_material_overrides(Configuration& config,
                                                const MaterialOverrides& overrides);

// {"k_n": ..., "k_t": ..., "kt_ratio": ..., "mu": ..., "zeta": ..., "mu_wall": ...}, one line.
std::string material_json(const Material& material);

}  // namespace granstab
