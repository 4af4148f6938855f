#include "start_state.hpp"

#include <algorithm>
#include <cstdio>
#include <set>
#include <stdexcept>
#include <tuple>

#include "measurements.hpp"
#include "pair_search.hpp"

namespace granstab {
namespace {

std::string number(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%.6g", v);
  return s;
}

std::string contact_name(const Contacts& c, std::size_t k) {
  const int i = c.i[k], j = c.j[k];
  return "contact " + std::to_string(k) + " (disk " + std::to_string(i) +
         (is_wall(j) ? " with wall " + std::to_string(-j) : " and disk " + std::to_string(j)) + ")";
}

}  // namespace

StartStateReport check_start_state(const Configuration& config,
                                   const EquilibriumTolerances& tolerances,
                                   const SanityLimits& limits) {
  StartStateReport report;
  const Disks& d = config.disks;
  const Contacts& c = config.contacts;
  const double fraction = limits.max_overlap_fraction;
  const std::string limit =
      " of the smaller radius (limit sanity.max_overlap_fraction = " + number(fraction) + ")";
  std::set<std::tuple<int, int, int, int>> listed;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const int i = c.i[k], j = c.j[k];
    const double r = is_wall(j) ? d.radius[i] : std::min(d.radius[i], d.radius[j]);
    const double h = contact_frame(config, k).h;
    if (!(h <= fraction * r))  // also catches h = nan
      report.geometry.push_back(contact_name(c, k) + ": overlap " + number(h) + " = " +
                                number(h / r) + limit);
    else if (!is_wall(j) && -h > fraction * r)
      report.geometry.push_back(contact_name(c, k) + ": listed, but the disks are " + number(-h) +
                                " apart = " + number(-h / r) + limit);
    if (!is_wall(j)) {
      // The pair search gives i < j with the image of j seen from i.
      if (i < j)
        listed.insert({i, j, c.k1[k], c.k2[k]});
      else
        listed.insert({j, i, -c.k1[k], -c.k2[k]});
    }
  }
  const PairList overlapping = find_pairs(d.x, d.y, d.radius, config.cell, 0.0);
  for (std::size_t p = 0; p < overlapping.size(); ++p) {
    const int i = overlapping.i[p], j = overlapping.j[p];
    if (listed.count({i, j, overlapping.k1[p], overlapping.k2[p]})) continue;
    // The search's test is on the gap; confirm the overlap with the contact law's geometry.
    const double lx = d.x[j] + overlapping.k1[p] * config.cell.length[0] - d.x[i];
    const double ly = d.y[j] + overlapping.k2[p] * config.cell.length[1] - d.y[i];
    const double h = disk_disk_frame(lx, ly, d.radius[i], d.radius[j]).h;
    if (!(h > 0.0)) continue;
    report.geometry.push_back("disks " + std::to_string(i) + " and " + std::to_string(j) +
                              " overlap by " + number(h) + " but are not in the contact list");
  }
  if (!config.cell.periodic()) {
    std::set<std::pair<int, int>> listed_walls;
    for (std::size_t k = 0; k < c.size(); ++k)
      if (is_wall(c.j[k])) listed_walls.insert({c.i[k], c.j[k]});
    for (std::size_t i = 0; i < d.size(); ++i)
      for (const Wall w : {wall_left, wall_right, wall_bottom, wall_top}) {
        const double h = disk_wall_frame(d.x[i], d.y[i], d.radius[i], w, config.cell).h;
        if (h > 0.0 && !listed_walls.count({static_cast<int>(i), static_cast<int>(w)}))
          report.geometry.push_back("disk " + std::to_string(i) + " overlaps wall " +
                                    std::to_string(-w) + " by " + number(h) +
                                    " but the contact is not in the list");
      }
  }
  report.equilibrium = check_equilibrium(config, tolerances);
  return report;
}

std::vector<std::string> equilibrium_failures(const EquilibriumReport& e,
                                              const EquilibriumTolerances& t) {
  std::vector<std::string> out;
  if (!e.force_ok)
    out.push_back("net force " + number(e.max_net_force) + " on disk " +
                  std::to_string(e.max_force_disk) + " (tolerance " + number(t.force) + " aP)");
  if (!e.torque_ok)
    out.push_back("net torque " + number(e.max_net_torque) + " on disk " +
                  std::to_string(e.max_torque_disk) + " (tolerance " + number(t.torque) +
                  " a^2 P)");
  if (!e.stress_ok)
    for (int a = 0; a < 2; ++a)
      if (e.stress_checked[a] && !(e.stress_error[a] < t.stress))
        out.push_back("stress " + std::to_string(a + 1) + " off its prescribed value by " +
                      number(e.stress_error[a]) + " (relative tolerance " + number(t.stress) + ")");
  return out;
}

void validate_start_state(const Configuration& config, const std::string& source,
                          bool allow_unbalanced) {
  const StartStateReport r = check_start_state(config);
  if (!r.geometry_ok()) {
    std::string what = source + ": the start state's geometry is broken";
    const std::size_t shown = std::min<std::size_t>(r.geometry.size(), 5);
    for (std::size_t k = 0; k < shown; ++k) what += "\n  " + r.geometry[k];
    if (r.geometry.size() > shown)
      what += "\n  ... and " + std::to_string(r.geometry.size() - shown) + " more";
    throw std::invalid_argument(what);
  }
  if (!allow_unbalanced && !r.equilibrium.in_equilibrium) {
    std::string what = source + ": the start state is not in equilibrium (SPEC §3.1)";
    for (const std::string& f : equilibrium_failures(r.equilibrium)) what += "\n  " + f;
    what += "\n  (--polish moves it to equilibrium first and reports how far)";
    throw std::invalid_argument(what);
  }
}

}  // namespace granstab
