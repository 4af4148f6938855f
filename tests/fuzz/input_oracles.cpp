#include "input_oracles.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <cstdint>
#include <exception>
#include <limits>
#include <stdexcept>
#include <typeinfo>
#include <vector>

#include "common/io/configuration_file.hpp"
#include "common/material_override.hpp"
#include "common/measurements.hpp"
#include "common/run_config.hpp"

namespace granstab::fuzz {
namespace {

// Reads a decimal number at the front of s (advancing s); -1 when there is none.
long long leading_number(std::string_view& s) {
  std::size_t n = 0;
  long long v = 0;
  while (n < s.size() && n < 12 && s[n] >= '0' && s[n] <= '9') v = 10 * v + (s[n++] - '0');
  if (n == 0) return -1;
  s.remove_prefix(n);
  return v;
}

long long line_count(std::string_view input) {
  return 1 + static_cast<long long>(std::count(input.begin(), input.end(), '\n'));
}

// "" if message is "SOURCE:LINE: text" (with_column: "SOURCE:LINE:COLUMN: text") and LINE is a
// line of the input; otherwise what is wrong with it.
std::string located_message_problem(std::string_view message, std::string_view source,
                                    std::string_view input, bool with_column) {
  const std::string quoted = "'" + std::string(message) + "'";
  std::string_view rest = message;
  if (!rest.starts_with(source) || rest.substr(source.size(), 1) != ":")
    return "message does not start with '" + std::string(source) + ":': " + quoted;
  rest.remove_prefix(source.size() + 1);
  const long long line = leading_number(rest);
  if (line < 1 || line > line_count(input))
    return "message names no line of the input (it has " + std::to_string(line_count(input)) +
           "): " + quoted;
  if (with_column) {
    if (!rest.starts_with(":")) return "message names no column: " + quoted;
    rest.remove_prefix(1);
    if (leading_number(rest) < 1) return "message names no column: " + quoted;
  }
  if (!rest.starts_with(": ") || rest.size() <= 2)
    return "message has no text after the place: " + quoted;
  return {};
}

std::string unexpected(std::string_view reader, const std::exception& e) {
  return std::string(reader) + " threw " + typeid(e).name() + ": '" + e.what() + "'";
}

}  // namespace

std::string configuration_violation(std::string_view input) {
  const std::string source(configuration_source);
  Configuration config;
  try {
    config = parse_configuration(input, source);
  } catch (const std::runtime_error& e) {
    return located_message_problem(e.what(), source, input, false);
  } catch (const std::exception& e) {
    return unexpected("parse_configuration", e);
  } catch (...) {
    return "parse_configuration threw a non-standard exception";
  }
  // Accepted: what was read must be writable, and read back to the same state.
  try {
    const std::string text = format_configuration(config);
    if (format_configuration(parse_configuration(text, "round-trip")) != text)
      return "an accepted input does not read back to the same configuration";
  } catch (const std::exception& e) {
    return "an accepted input cannot be written and read back: " + std::string(e.what());
  }
  return {};
}

std::string run_config_violation(std::string_view input) {
  const std::string source(run_config_source);
  std::vector<std::string> overrides;
  for (std::size_t pos = 0; pos < input.size();) {
    std::size_t end = input.find('\n', pos);
    if (end == std::string_view::npos) end = input.size();
    const std::string_view line = input.substr(pos, end - pos);
    if (line.starts_with("#set ")) overrides.emplace_back(line.substr(5));
    pos = end + 1;
  }
  try {
    RunConfig rc = RunConfig::from_string(input, source, overrides, "/base");
    // A protocol's kind of schema (dynamic/protocols/settings.cpp and friends).
    rc.number("material.kappa", 1e4, 1.0, 1e9);
    rc.number("material.mu", 0.3, 0.0, 100.0);
    rc.number("material.zeta", 0.9, 0.0, 1.0);
    rc.integer("equilibrium.check_interval", 100, 1, 100'000'000);
    rc.integer("equilibrium.max_steps", 1'000'000, 0, std::numeric_limits<std::int64_t>::max());
    rc.boolean("output.vtk", false);
    rc.choice("biaxial.mode", "SRC", {"SRC", "SIC"});
    rc.string("run.name", "run");
    if (rc.contains("sample.file")) rc.path("sample.file");
    rc.path("output.directory");
    rc.finish();
  } catch (const std::runtime_error& e) {
    return located_message_problem(e.what(), source, input, true);
  } catch (const std::invalid_argument& e) {
    const std::string_view message = e.what();
    if (!message.starts_with(source + ": ") && !message.starts_with("command line"))
      return "a setting error names neither the file nor the command line: '" +
             std::string(message) + "'";
    return {};
  } catch (const std::exception& e) {
    return unexpected("RunConfig", e);
  } catch (...) {
    return "RunConfig threw a non-standard exception";
  }
  return {};
}

std::string material_options_violation(std::string_view input) {
  Configuration config;
  config.cell.length = {10.0, 10.0};
  config.material = Material::from_kappa(1e4, 1.0, 0.5, 1.0);
  config.disks.add(4.0, 5.0, 0.5);
  config.disks.add(4.999, 5.0, 0.5);
  // Overlap 1e-3: F_N = 10; F_T = -K_T delta_t = 2, inside the cone of mu = 0.5.
  config.contacts.add(0, 1, 0, 0, -2e-4);
  MaterialOverrides o;
  std::string_view rest = input;
  while (!rest.empty()) {
    const std::size_t end = std::min(rest.find('\n'), rest.size());
    const std::string_view line = rest.substr(0, end);
    rest.remove_prefix(std::min(end + 1, rest.size()));
    const auto number = [&](std::size_t skip) {
      double v = std::numeric_limits<double>::quiet_NaN();
      if (line.size() > skip) std::from_chars(line.data() + skip, line.data() + line.size(), v);
      return v;
    };
    try {
      if (line.starts_with("mu "))
        o.mu = number(3);
      else if (line.starts_with("kt_ratio "))
        o.kt_ratio = number(9);
      else if (line.starts_with("set "))
        o.set.push_back(parse_material_setting(std::string(line.substr(4))));
      else if (line == "clip")
        o.clip_to_cone = true;
    } catch (const std::invalid_argument&) {
      return "";  // a rejected --set text
    } catch (const std::exception& e) {
      return std::string("parse_material_setting threw ") + typeid(e).name() + ": " + e.what();
    }
  }
  const double f_t_before = -config.material.k_t * config.contacts.delta_t[0];
  try {
    apply_material_overrides(config, o);
  } catch (const std::invalid_argument&) {
    return "";
  } catch (const std::exception& e) {
    return std::string("apply_material_overrides threw ") + typeid(e).name() + ": " + e.what();
  }
  try {
    validate(config.material);
  } catch (const std::exception& e) {
    return std::string("accepted an invalid material: ") + e.what();
  }
  const double f_n = config.material.k_n * contact_frame(config, 0).h;
  const double f_t = -config.material.k_t * config.contacts.delta_t[0];
  if (!(std::abs(f_t) <= config.material.mu * f_n * (1.0 + 1e-9)))
    return "accepted a contact outside its cone";
  if (!o.clip_to_cone && !(std::abs(f_t - f_t_before) <= 1e-12 * std::abs(f_t_before)))
    return "changed the tangential force without clipping";
  return "";
}

}  // namespace granstab::fuzz
