#include "json_summary.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

#include "common/atomic_file.hpp"

namespace granstab::protocols {

JsonObject& JsonObject::add(std::string_view key, double value) {
  members_.emplace_back(key, json_number(value));
  return *this;
}
JsonObject& JsonObject::add(std::string_view key, std::int64_t value) {
  members_.emplace_back(key, std::to_string(value));
  return *this;
}
JsonObject& JsonObject::add(std::string_view key, std::uint64_t value) {
  members_.emplace_back(key, std::to_string(value));
  return *this;
}
JsonObject& JsonObject::add(std::string_view key, bool value) {
  members_.emplace_back(key, value ? "true" : "false");
  return *this;
}
JsonObject& JsonObject::add(std::string_view key, std::string_view value) {
  members_.emplace_back(key, json_string(value));
  return *this;
}
JsonObject& JsonObject::add(std::string_view key, const std::vector<double>& values) {
  std::string v = "[";
  for (std::size_t k = 0; k < values.size(); ++k) v += (k ? ", " : "") + json_number(values[k]);
  members_.emplace_back(key, v + "]");
  return *this;
}
// A nested object is stored as its text at depth 0; text() indents its lines to the depth.
JsonObject& JsonObject::add(std::string_view key, const JsonObject& object) {
  members_.emplace_back(key, object.text(0));
  return *this;
}
JsonObject& JsonObject::add(std::string_view key, const std::vector<JsonObject>& objects) {
  std::string v = "[";
  for (std::size_t k = 0; k < objects.size(); ++k) {
    v += (k ? ",\n" : "\n") + std::string(2, ' ');
    for (const char ch : objects[k].text(0)) {
      v += ch;
      if (ch == '\n') v += "  ";
    }
  }
  members_.emplace_back(key, v + (objects.empty() ? "]" : "\n]"));
  return *this;
}

std::string JsonObject::text(int indent) const {
  const std::string pad(static_cast<std::size_t>(indent), ' ');
  std::string out = "{";
  for (std::size_t k = 0; k < members_.size(); ++k) {
    out += k ? ",\n" : "\n";
    out += pad + "  " + json_string(members_[k].first) + ": ";
    for (const char ch : members_[k].second) {
      out += ch;
      if (ch == '\n') out += pad + "  ";
    }
  }
  out += members_.empty() ? "}" : "\n" + pad + "}";
  return out;
}

JsonObject measurements_json(const Measurements& m) {
  JsonObject o;
  o.add("n_disks", static_cast<std::uint64_t>(m.n_disks))
      .add("phi", m.phi)
      .add("z", m.z)
      .add("x0", m.x0)
      .add("x_s", m.x_s)
      .add("rattlers", static_cast<std::uint64_t>(m.n_rattlers))
      .add("contacts_carrying", static_cast<std::uint64_t>(m.n_contacts_carrying))
      .add("contacts_sliding", static_cast<std::uint64_t>(m.n_sliding))
      .add("sigma", std::vector<double>{m.sigma[0][0], m.sigma[0][1], m.sigma[1][0], m.sigma[1][1]})
      .add("q", m.q)
      .add("epsilon_1", m.epsilon_1)
      .add("epsilon_2", m.epsilon_2)
      .add("epsilon_v", m.epsilon_v)
      .add("e_c", m.e_c)
      .add("f_2", m.f_2)
      .add("torque_2", m.torque_2);
  return o;
}

JsonObject equilibrium_json(const EquilibriumReport& r, const EquilibriumTolerances& t) {
  JsonObject o;
  o.add("in_equilibrium", r.in_equilibrium)
      .add("max_net_force", r.max_net_force)
      .add("max_net_torque", r.max_net_torque)
      .add("stress_error", std::vector<double>{r.stress_checked[0] ? r.stress_error[0] : NAN,
                                               r.stress_checked[1] ? r.stress_error[1] : NAN})
      .add("e_c", r.e_c)
      .add("f_2", r.f_2)
      .add("tolerance_force", t.force)
      .add("tolerance_torque", t.torque)
      .add("tolerance_stress", t.stress);
  return o;
}

void write_json(const std::filesystem::path& path, const JsonObject& object) {
  write_file_atomically(path, object.text(0) + "\n");
}

}  // namespace granstab::protocols
