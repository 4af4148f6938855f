#include "checkpoint.hpp"

#include <charconv>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/io/configuration_file.hpp"
#include "common/io/csv_writer.hpp"

namespace granstab::protocols {
namespace {

constexpr std::string_view magic = "granstab-checkpoint";

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw std::runtime_error(source + ": " + what);
}

}  // namespace

std::uint64_t fnv1a64(std::string_view bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

void Checkpoint::set(std::string_view name, std::string_view value) {
  if (name.empty() || name.find_first_of(" \n") != std::string_view::npos || name == "end") {
    throw std::invalid_argument("checkpoint: bad entry name '" + std::string(name) + "'");
  }
  for (auto& [n, v] : entries_) {
    if (n == name) {
      v = value;
      return;
    }
  }
  entries_.emplace_back(name, value);
}

void Checkpoint::set_number(std::string_view name, double value) {
  // csv_number: the shortest decimal that reads back to the same bits ("nan", "inf" otherwise).
  set(name, csv_number(value));
}

void Checkpoint::set_count(std::string_view name, std::uint64_t value) {
  set(name, std::to_string(value));
}

void Checkpoint::set_flag(std::string_view name, bool value) { set(name, value ? "1" : "0"); }

void Checkpoint::set_configuration(std::string_view name, const Configuration& config) {
  set(name, format_configuration(config));
}

void Checkpoint::set_report(std::string_view prefix, const EquilibriumReport& r) {
  const std::string p(prefix);
  set_number(p + ".max_net_force", r.max_net_force);
  set_number(p + ".max_net_torque", r.max_net_torque);
  set_count(p + ".max_force_disk", r.max_force_disk);
  set_count(p + ".max_torque_disk", r.max_torque_disk);
  for (int a = 0; a < 2; ++a) {
    set_number(p + ".stress_error_" + std::to_string(a + 1), r.stress_error[a]);
    set_flag(p + ".stress_checked_" + std::to_string(a + 1), r.stress_checked[a]);
  }
  set_number(p + ".e_c", r.e_c);
  set_number(p + ".f_2", r.f_2);
  set_flag(p + ".force_ok", r.force_ok);
  set_flag(p + ".torque_ok", r.torque_ok);
  set_flag(p + ".stress_ok", r.stress_ok);
  set_flag(p + ".in_equilibrium", r.in_equilibrium);
}

bool Checkpoint::has(std::string_view name) const {
  for (const auto& e : entries_) {
    if (e.first == name) return true;
  }
  return false;
}

const std::string& Checkpoint::text(std::string_view name) const {
  for (const auto& e : entries_) {
    if (e.first == name) return e.second;
  }
  fail(source_, "entry " + std::string(name) + ": missing");
}

double Checkpoint::number(std::string_view name) const {
  const std::string& t = text(name);
  double v = 0.0;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  if (r.ec != std::errc() || r.ptr != t.data() + t.size()) {
    fail(source_, "entry " + std::string(name) + " = '" + t + "': not a number");
  }
  return v;
}

std::uint64_t Checkpoint::count(std::string_view name) const {
  const std::string& t = text(name);
  std::uint64_t v = 0;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  if (r.ec != std::errc() || r.ptr != t.data() + t.size()) {
    fail(source_, "entry " + std::string(name) + " = '" + t + "': not a count");
  }
  return v;
}

bool Checkpoint::flag(std::string_view name) const {
  const std::string& t = text(name);
  if (t != "0" && t != "1") fail(source_, "entry " + std::string(name) + ": not 0 or 1");
  return t == "1";
}

Configuration Checkpoint::configuration(std::string_view name) const {
  return parse_configuration(text(name), source_ + " [" + std::string(name) + "]");
}

EquilibriumReport Checkpoint::report(std::string_view prefix) const {
  const std::string p(prefix);
  EquilibriumReport r;
  r.max_net_force = number(p + ".max_net_force");
  r.max_net_torque = number(p + ".max_net_torque");
  r.max_force_disk = count(p + ".max_force_disk");
  r.max_torque_disk = count(p + ".max_torque_disk");
  for (int a = 0; a < 2; ++a) {
    r.stress_error[a] = number(p + ".stress_error_" + std::to_string(a + 1));
    r.stress_checked[a] = flag(p + ".stress_checked_" + std::to_string(a + 1));
  }
  r.e_c = number(p + ".e_c");
  r.f_2 = number(p + ".f_2");
  r.force_ok = flag(p + ".force_ok");
  r.torque_ok = flag(p + ".torque_ok");
  r.stress_ok = flag(p + ".stress_ok");
  r.in_equilibrium = flag(p + ".in_equilibrium");
  return r;
}

std::string Checkpoint::format() const {
  std::string out(magic);
  out += ' ' + std::to_string(checkpoint_format_version) + '\n';
  for (const auto& [name, value] : entries_) {
    out += name + ' ' + std::to_string(value.size()) + '\n';
    out += value;
    out += '\n';
  }
  out += "end " + std::to_string(fnv1a64(out)) + '\n';
  return out;
}

Checkpoint Checkpoint::parse(std::string_view text, const std::string& source_name) {
  Checkpoint c;
  c.source_ = source_name;
  const auto line_end = [&](std::size_t from) {
    const std::size_t e = text.find('\n', from);
    if (e == std::string_view::npos) fail(source_name, "truncated (no end line)");
    return e;
  };
  std::size_t pos = line_end(0);
  const std::string header(text.substr(0, pos));
  if (header != std::string(magic) + " " + std::to_string(checkpoint_format_version)) {
    fail(source_name, "not a granstab checkpoint of format version " +
                          std::to_string(checkpoint_format_version) + " (first line '" +
                          header.substr(0, 60) + "')");
  }
  ++pos;
  for (;;) {
    const std::size_t e = line_end(pos);
    const std::string_view line = text.substr(pos, e - pos);
    const std::size_t space = line.find(' ');
    if (space == std::string_view::npos) fail(source_name, "malformed entry line");
    const std::string_view name = line.substr(0, space), number = line.substr(space + 1);
    std::uint64_t value = 0;
    const auto r = std::from_chars(number.data(), number.data() + number.size(), value);
    if (r.ec != std::errc() || r.ptr != number.data() + number.size()) {
      fail(source_name, "malformed entry line '" + std::string(line.substr(0, 60)) + "'");
    }
    if (name == "end") {
      if (value != fnv1a64(text.substr(0, pos))) fail(source_name, "checksum mismatch (damaged)");
      if (e + 1 != text.size()) fail(source_name, "data after the end line");
      return c;
    }
    if (value > text.size() - (e + 1) || text.size() - (e + 1) - value < 1 ||
        text[e + 1 + value] != '\n') {
      fail(source_name, "entry " + std::string(name) + ": truncated");
    }
    c.entries_.emplace_back(name, text.substr(e + 1, value));
    pos = e + 1 + value + 1;
  }
}

void Checkpoint::write(const std::filesystem::path& path) const {
  write_file_atomically(path, format());
}

Checkpoint Checkpoint::read(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open the checkpoint");
  std::ostringstream s;
  s << in.rdbuf();
  return parse(s.str(), path.string());
}

void put_cursor(Checkpoint& c, const Cursor& cursor) {
  c.set_count("cursor.phase", static_cast<std::uint64_t>(cursor.phase));
  c.set_count("cursor.index", static_cast<std::uint64_t>(cursor.index));
  c.set_count("cursor.steps", cursor.steps);
  c.set_count("cursor.done_steps", cursor.done_steps);
  c.set_number("cursor.next_record", cursor.next_record);
  c.set_count("cursor.values", cursor.values.size());
  for (std::size_t k = 0; k < cursor.values.size(); ++k) {
    c.set_number("cursor.value_" + std::to_string(k), cursor.values[k]);
  }
  c.set("cursor.rng_state", cursor.rng_state);
  c.set_report("cursor.report", cursor.report);
}

Cursor get_cursor(const Checkpoint& c) {
  Cursor cursor;
  cursor.phase = static_cast<int>(c.count("cursor.phase"));
  cursor.index = static_cast<std::int64_t>(c.count("cursor.index"));
  cursor.steps = c.count("cursor.steps");
  cursor.done_steps = c.count("cursor.done_steps");
  cursor.next_record = c.number("cursor.next_record");
  const std::uint64_t n = c.count("cursor.values");
  if (n > 1000) fail(c.source_name(), "entry cursor.values: too many");
  cursor.values.resize(n);
  for (std::size_t k = 0; k < cursor.values.size(); ++k) {
    cursor.values[k] = c.number("cursor.value_" + std::to_string(k));
  }
  cursor.rng_state = c.text("cursor.rng_state");
  cursor.report = c.report("cursor.report");
  return cursor;
}

}  // namespace granstab::protocols
