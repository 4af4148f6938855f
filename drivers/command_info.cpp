// granstab info SAMPLE: the SPEC §2 measurements and the §3.1 equilibrium residuals of a
// configuration file, as text or JSON. Reading, measuring and checking live in common/.
#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include "commands.hpp"
#include "common/start_state.hpp"
#include "common/equilibrium.hpp"
#include "common/io/configuration_file.hpp"
#include "common/io/json_text.hpp"
#include "common/measurements.hpp"

namespace granstab::cli {
namespace {

struct InfoOptions {
  std::string sample;
  bool json = false;
  EquilibriumTolerances tolerances;
};

std::string_view control_name(LengthControl c) {
  switch (c) {
    case LengthControl::stress:
      return "stress";
    case LengthControl::strain_rate:
      return "strain_rate";
    case LengthControl::fixed:
      return "fixed";
  }
  return "?";
}

// Text: ten significant digits are plenty to read; the file itself keeps every bit.
std::string text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string pass(bool ok) { return ok ? "pass" : "FAIL"; }

// With walls, SPEC §2's second stress measure: the forces on the mobile walls over their lengths.
std::string wall_stress_text(const Configuration& c) {
  if (c.cell.periodic()) return {};
  const auto f = wall_forces(c, contact_loads(c));
  return "wall stress      " + text(f[1] / c.cell.length[1]) + " " + text(f[3] / c.cell.length[0]) +
         "  (F_right / L2, F_top / L1)\n";
}

void print_text(const InfoOptions& o, const Configuration& c, const Measurements& m,
                const StartStateReport& start, std::ostream& out) {
  const EquilibriumReport& r = start.equilibrium;
  const auto& L = c.cell.length;
  out << "sample           " << o.sample << "\n"
      << "N                " << m.n_disks << "\n"
      << "boundary         " << (c.cell.periodic() ? "periodic" : "walls") << "\n"
      << "L1 L2            " << text(L[0]) << " " << text(L[1]) << "\n"
      << "time step        " << text(c.time) << " " << c.step << "\n"
      << "Phi              " << text(m.phi) << "\n"
      << "contacts         " << m.n_contacts_listed << " listed, " << m.n_contacts_carrying
      << " carrying force, " << m.n_sliding << " sliding\n"
      << "z                " << text(m.z) << "  (" << m.n_network_disk_disk << " disk-disk + "
      << m.n_network_wall << " wall contacts over " << m.n_disks - m.n_rattlers << " disks)\n"
      << "x0               " << text(m.x0) << "  (" << m.n_rattlers << " rattlers)\n"
      << "X_s              " << text(m.x_s) << "\n"
      << "sigma            " << text(m.sigma[0][0]) << " " << text(m.sigma[0][1]) << " / "
      << text(m.sigma[1][0]) << " " << text(m.sigma[1][1]) << "  (s11 s12 / s21 s22)\n"
      << wall_stress_text(c) << "q                " << text(m.q) << "\n"
      << "eps1 eps2 epsv   " << text(m.epsilon_1) << " " << text(m.epsilon_2) << " "
      << text(m.epsilon_v) << "\n"
      << "e_c              " << text(m.e_c) << "\n"
      << "f_2              " << text(m.f_2) << "  (torque: " << text(m.torque_2) << ")\n"
      << "equilibrium (SPEC 3.1)\n"
      << "  max net force  " << text(r.max_net_force) << "  < " << text(o.tolerances.force) << "  "
      << pass(r.force_ok) << "\n"
      << "  max net torque " << text(r.max_net_torque) << "  < " << text(o.tolerances.torque)
      << "  " << pass(r.torque_ok) << "\n";
  for (int a = 0; a < 2; ++a) {
    out << "  sigma_" << a + 1 << " error  ";
    if (r.stress_checked[a])
      out << text(r.stress_error[a]) << "  < " << text(o.tolerances.stress) << "  "
          << pass(r.stress_error[a] < o.tolerances.stress) << "  (target "
          << text(c.stage.sigma_ext[a]) << ")\n";
    else
      out << "not checked (control: " << control_name(c.stage.control[a]) << ")\n";
  }
  out << "  in equilibrium " << (r.in_equilibrium ? "yes" : "no") << "\n";
  // What the static commands check before they start (common/start_state.hpp).
  out << "start state (static runs)\n  geometry       " << (start.geometry_ok() ? "pass" : "FAIL")
      << "\n";
  for (const std::string& g : start.geometry) out << "    " << g << "\n";
  out << "  equilibrium    "
      << (r.in_equilibrium ? "pass" : "FAIL (q1, compare and probe need --polish)") << "\n";
  for (const std::string& f : equilibrium_failures(r, o.tolerances)) out << "    " << f << "\n";
}

std::string json(double v) { return json_number(v); }
std::string json(std::string_view s) { return json_string(s); }
std::string json(const char* s) { return json(std::string_view(s)); }
std::string json(bool b) { return b ? "true" : "false"; }

void print_json(const InfoOptions& o, const Configuration& c, const Measurements& m,
                const StartStateReport& start, std::ostream& out) {
  const EquilibriumReport& r = start.equilibrium;
  const auto& s = m.sigma;
  out << "{\n"
      << "  \"sample\": " << json(o.sample) << ",\n"
      << "  \"n_disks\": " << m.n_disks << ",\n"
      << "  \"boundary\": " << json(c.cell.periodic() ? "periodic" : "walls") << ",\n"
      << "  \"length\": [" << json(c.cell.length[0]) << ", " << json(c.cell.length[1]) << "],\n"
      << "  \"time\": " << json(c.time) << ",\n"
      << "  \"step\": " << c.step << ",\n"
      << "  \"phi\": " << json(m.phi) << ",\n"
      << "  \"contacts_listed\": " << m.n_contacts_listed << ",\n"
      << "  \"contacts_carrying\": " << m.n_contacts_carrying << ",\n"
      << "  \"contacts_sliding\": " << m.n_sliding << ",\n"
      << "  \"network_disk_disk\": " << m.n_network_disk_disk << ",\n"
      << "  \"network_wall\": " << m.n_network_wall << ",\n"
      << "  \"rattlers\": " << m.n_rattlers << ",\n"
      << "  \"z\": " << json(m.z) << ",\n"
      << "  \"x0\": " << json(m.x0) << ",\n"
      << "  \"x_s\": " << json(m.x_s) << ",\n"
      << "  \"sigma\": [[" << json(s[0][0]) << ", " << json(s[0][1]) << "], [" << json(s[1][0])
      << ", " << json(s[1][1]) << "]],\n"
      << "  \"q\": " << json(m.q) << ",\n"
      << "  \"epsilon_1\": " << json(m.epsilon_1) << ",\n"
      << "  \"epsilon_2\": " << json(m.epsilon_2) << ",\n"
      << "  \"epsilon_v\": " << json(m.epsilon_v) << ",\n"
      << "  \"e_c\": " << json(m.e_c) << ",\n"
      << "  \"f_2\": " << json(m.f_2) << ",\n"
      << "  \"torque_2\": " << json(m.torque_2) << ",\n"
      << "  \"equilibrium\": {\n"
      << "    \"tolerance_force\": " << json(o.tolerances.force) << ",\n"
      << "    \"tolerance_torque\": " << json(o.tolerances.torque) << ",\n"
      << "    \"tolerance_stress\": " << json(o.tolerances.stress) << ",\n"
      << "    \"max_net_force\": " << json(r.max_net_force) << ",\n"
      << "    \"max_net_torque\": " << json(r.max_net_torque) << ",\n"
      << "    \"stress_error\": [" << (r.stress_checked[0] ? json(r.stress_error[0]) : "null")
      << ", " << (r.stress_checked[1] ? json(r.stress_error[1]) : "null") << "],\n"
      << "    \"force_ok\": " << json(r.force_ok) << ",\n"
      << "    \"torque_ok\": " << json(r.torque_ok) << ",\n"
      << "    \"stress_ok\": " << json(r.stress_ok) << ",\n"
      << "    \"in_equilibrium\": " << json(r.in_equilibrium) << "\n"
      << "  },\n"
      << "  \"geometry_problems\": [";
  for (std::size_t k = 0; k < start.geometry.size(); ++k)
    out << (k ? ", " : "") << json(std::string_view(start.geometry[k]));
  out << "]\n"
      << "}\n";
}

void run_info(const InfoOptions& o) {
  const Configuration config = read_configuration(o.sample);
  const Measurements measured = measure(config);
  const StartStateReport report = check_start_state(config, o.tolerances);
  // Formatted in full before printing: an error never leaves half a report on stdout.
  std::ostringstream out;
  if (o.json)
    print_json(o, config, measured, report, out);
  else
    print_text(o, config, measured, report, out);
  std::cout << out.str() << std::flush;
  // A broken geometry is an error (exit 1); a state out of equilibrium is a finding (exit 0).
  if (!report.geometry_ok())
    throw std::runtime_error(o.sample + ": the geometry is broken (" +
                             std::to_string(report.geometry.size()) + " problems, listed above)");
}

}  // namespace

void add_info_command(CLI::App& app) {
  auto options = std::make_shared<InfoOptions>();
  auto* cmd = app.add_subcommand(
      "info",
      "Print N, cell, Phi, z, x0, X_s, stress tensor, q, strains, e_c, f_2 (SPEC §2) and "
      "the equilibrium residuals (SPEC §3.1) of a configuration file");
  cmd->add_option("SAMPLE", options->sample, "configuration file (docs/file-format.md)")
      ->required();
  cmd->add_flag("--json", options->json, "print the same quantities as JSON");
  cmd->add_option("--force-tolerance", options->tolerances.force,
                  "largest net force on a non-rattler disk, units aP")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--torque-tolerance", options->tolerances.torque,
                  "largest net torque on a non-rattler disk, units a^2 P")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--stress-tolerance", options->tolerances.stress,
                  "largest relative error of a stress-controlled component")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->callback([options] { run_info(*options); });
}

}  // namespace granstab::cli
