#include "run_config.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <set>
#include <stdexcept>
#include <toml++/toml.h>

namespace granstab {
namespace {

std::vector<std::string> split_key(std::string_view key) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    parts.emplace_back(key.substr(start, dot == std::string_view::npos ? dot : dot - start));
    if (dot == std::string_view::npos) break;
    start = dot + 1;
  }
  return parts;
}

template <class T>
std::string shortest(T v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// How a value is shown in messages: TOML-like, short.
std::string show(const toml::node& node) {
  if (const auto* s = node.as_string()) return "\"" + s->get() + "\"";
  if (const auto* i = node.as_integer()) return shortest(i->get());
  if (const auto* f = node.as_floating_point()) return shortest(f->get());
  if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
  if (node.is_table()) return "(a table)";
  if (node.is_array()) return "(an array)";
  return "(a date/time)";
}

std::string trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t");
  return std::string(s.substr(first, last - first + 1));
}

}  // namespace

struct RunConfig::Impl {
  toml::table root;
  std::string source;
  std::filesystem::path base_dir;
  std::set<std::string, std::less<>> read;
  std::set<std::string, std::less<>> overridden;

  // The source a key's value came from, for messages.
  std::string origin(std::string_view key) const {
    return overridden.contains(key) ? "command line (--set " + std::string(key) + "=...)" : source;
  }

  [[noreturn]] void fail(std::string_view key, const toml::node& node, const std::string& what) const {
    throw std::invalid_argument(origin(key) + ": " + std::string(key) + " = " + show(node) + ": " + what);
  }

  // The node at a dotted key, or nullptr; marks the key as read.
  const toml::node* find(std::string_view key) {
    read.emplace(key);
    return lookup(key);
  }
  const toml::node* lookup(std::string_view key) const {
    const toml::table* table = &root;
    const auto parts = split_key(key);
    std::string prefix;
    for (std::size_t p = 0; p < parts.size(); ++p) {
      const toml::node* node = table->get(parts[p]);
      if (!node) return nullptr;
      if (p + 1 == parts.size()) return node;
      prefix += (p ? "." : "") + parts[p];
      table = node->as_table();
      if (!table)
        throw std::invalid_argument(origin(prefix) + ": " + prefix + " = " + show(*node) +
                                    ": must be a table (it holds " + std::string(key) + ")");
    }
    return nullptr;
  }

  void apply_override(const std::string& assignment) {
    const auto eq = assignment.find('=');
    const std::string key = eq == std::string::npos ? std::string{} : trim(assignment.substr(0, eq));
    if (key.empty())
      throw std::invalid_argument("command line: '" + assignment + "': overrides read key=value");
    const std::string text = trim(std::string_view(assignment).substr(eq + 1));
    toml::table parsed;
    try {
      parsed = toml::parse("value = " + text, std::string_view{"--set"});
    } catch (const toml::parse_error&) {
      parsed = toml::table{};
      parsed.insert("value", text);  // not TOML: a bare word stands for a string
    }
    const auto parts = split_key(key);
    toml::table* table = &root;
    std::string prefix;
    for (std::size_t p = 0; p + 1 < parts.size(); ++p) {
      prefix += (p ? "." : "") + parts[p];
      toml::node* node = table->get(parts[p]);
      if (!node) node = &table->insert(parts[p], toml::table{}).first->second;
      table = node->as_table();
      if (!table)
        throw std::invalid_argument("command line: --set " + assignment + ": " + prefix +
                                    " is not a table");
    }
    parsed.get("value")->visit(
        [&](auto& value) { table->insert_or_assign(parts.back(), std::move(value)); });
    overridden.insert(key);
  }

  void collect_unread(const toml::table& table, const std::string& prefix,
                      std::vector<std::string>& unread) const {
    for (const auto& [k, node] : table) {
      const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
      if (read.contains(key)) continue;
      const auto* sub = node.as_table();
      if (sub && !sub->empty())
        collect_unread(*sub, key, unread);
      else
        unread.push_back(key);
    }
  }
};

RunConfig::RunConfig(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
RunConfig::RunConfig(RunConfig&&) noexcept = default;
RunConfig& RunConfig::operator=(RunConfig&&) noexcept = default;
RunConfig::~RunConfig() = default;

RunConfig RunConfig::from_string(std::string_view toml_text, const std::string& source_name,
                                 const std::vector<std::string>& overrides,
                                 const std::filesystem::path& base_dir) {
  auto impl = std::make_unique<Impl>();
  impl->source = source_name;
  impl->base_dir = base_dir;
  try {
    impl->root = toml::parse(toml_text, std::string_view{source_name});
  } catch (const toml::parse_error& e) {
    const auto& begin = e.source().begin;
    throw std::runtime_error(source_name + ":" + std::to_string(begin.line) + ":" +
                             std::to_string(begin.column) + ": " + std::string(e.description()));
  }
  for (const auto& assignment : overrides) impl->apply_override(assignment);
  return RunConfig(std::move(impl));
}

RunConfig RunConfig::from_file(const std::filesystem::path& file,
                               const std::vector<std::string>& overrides) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot open settings file");
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  return from_string(text, file.string(), overrides, file.parent_path());
}

double RunConfig::number(std::string_view key, double fallback, double min, double max) {
  const toml::node* node = impl_->find(key);
  if (!node) return fallback;
  double v = 0.0;
  if (const auto* f = node->as_floating_point())
    v = f->get();
  else if (const auto* i = node->as_integer())
    v = static_cast<double>(i->get());
  else
    impl_->fail(key, *node, "must be a number");
  if (!std::isfinite(v)) impl_->fail(key, *node, "must be finite");
  if (v < min) impl_->fail(key, *node, "must be >= " + shortest(min));
  if (v > max) impl_->fail(key, *node, "must be <= " + shortest(max));
  return v;
}

std::int64_t RunConfig::integer(std::string_view key, std::int64_t fallback, std::int64_t min,
                                std::int64_t max) {
  const toml::node* node = impl_->find(key);
  if (!node) return fallback;
  const auto* i = node->as_integer();
  if (!i) impl_->fail(key, *node, "must be an integer");
  if (i->get() < min) impl_->fail(key, *node, "must be >= " + shortest(min));
  if (i->get() > max) impl_->fail(key, *node, "must be <= " + shortest(max));
  return i->get();
}

bool RunConfig::boolean(std::string_view key, bool fallback) {
  const toml::node* node = impl_->find(key);
  if (!node) return fallback;
  const auto* b = node->as_boolean();
  if (!b) impl_->fail(key, *node, "must be true or false");
  return b->get();
}

std::string RunConfig::string(std::string_view key, const std::string& fallback) {
  const toml::node* node = impl_->find(key);
  if (!node) return fallback;
  const auto* s = node->as_string();
  if (!s) impl_->fail(key, *node, "must be a string");
  return s->get();
}

std::string RunConfig::choice(std::string_view key, const std::string& fallback,
                              const std::vector<std::string>& allowed) {
  const std::string value = string(key, fallback);
  if (std::find(allowed.begin(), allowed.end(), value) != allowed.end()) return value;
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  const toml::node* node = impl_->lookup(key);
  if (!node) throw std::logic_error("RunConfig::choice: default of " + std::string(key) + " not allowed");
  impl_->fail(key, *node, "must be one of " + list);
}

std::optional<std::filesystem::path> RunConfig::path(std::string_view key) {
  if (!contains(key)) {
    impl_->read.emplace(key);
    return std::nullopt;
  }
  std::filesystem::path p = string(key, {});
  if (p.empty()) impl_->fail(key, *impl_->lookup(key), "must not be empty");
  if (p.is_relative() && !impl_->overridden.contains(key) && !impl_->base_dir.empty())
    p = impl_->base_dir / p;
  return p;
}

bool RunConfig::contains(std::string_view key) const { return impl_->lookup(key) != nullptr; }

const std::string& RunConfig::source_name() const { return impl_->source; }

void RunConfig::finish() const {
  std::vector<std::string> unread;
  impl_->collect_unread(impl_->root, "", unread);
  if (unread.empty()) return;
  std::string list;
  for (const auto& k : unread) list += (list.empty() ? "" : ", ") + k;
  throw std::invalid_argument(impl_->source + ": unknown key" + (unread.size() > 1 ? "s" : "") +
                              " (not used by this command): " + list);
}

}  // namespace granstab
