#include "run_config.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
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

// toml++ 3.3.0 (Debian 12) reaches __builtin_unreachable, i.e. undefined behaviour, when its
// whitespace test sees a code point in these ranges (marzer/tomlplusplus#190 and #295, fixed
// upstream by PR #305). Found by tests/fuzz (docs/reliability.md). It tests every character of a
// key, the characters that follow a token, and what follows a backslash in a multi-line basic
// string; string values and comments are safe.
bool trips_toml_whitespace_bug(char32_t c) {
  return (c >= 0xA1 && c <= 0x499) || (c >= 0x2C5E && c <= 0x2FFF) ||
         (c >= 0x3001 && c <= 0x3057) || (c >= 0xFB26 && c <= 0xFEFE);
}

bool is_toml_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

// Rejects, with "SOURCE:LINE:COLUMN: message", a character that would reach the bug above. A
// light TOML scanner: it tracks comments, the four kinds of strings and brackets, and treats a
// string as a value only after '=' or inside an array; anything it is unsure of counts as a key.
void reject_toml_whitespace_bug(std::string_view text, const std::string& source) {
  enum class State { normal, comment, basic, literal, ml_basic, ml_literal };
  State state = State::normal;
  bool value_string = false;
  std::vector<char> brackets;  // 'h' table header, 'a' array value, 't' inline table
  char previous = '\n';        // last significant character outside strings and comments
  std::size_t i = 0;
  auto at_value = [&] {
    const bool in_array = !brackets.empty() && brackets.back() == 'a';
    return previous == '=' || (in_array && (previous == '[' || previous == ','));
  };
  // The code point starting at i (lenient: malformed UTF-8 is toml++'s to report).
  auto code_point = [&](std::size_t k) -> char32_t {
    const auto b = static_cast<unsigned char>(text[k]);
    const int n = b >= 0xF0 ? 3 : b >= 0xE0 ? 2 : b >= 0xC0 ? 1 : 0;
    char32_t c = n == 0 ? b : b & (0x3F >> n);
    for (int m = 1; m <= n && k + m < text.size(); ++m)
      c = (c << 6) | (static_cast<unsigned char>(text[k + m]) & 0x3F);
    return c;
  };
  auto check = [&](std::size_t k) {
    if (k >= text.size() || (static_cast<unsigned char>(text[k]) & 0xC0) == 0x80) return;
    const char32_t c = code_point(k);
    if (!trips_toml_whitespace_bug(c)) return;
    // The place, counted as toml++ does: lines from 1, columns in code points from 1.
    const std::string_view before = text.substr(0, k);
    const std::size_t line_start = before.rfind('\n') + 1;  // npos + 1 == 0
    const auto line = 1 + std::count(before.begin(), before.end(), '\n');
    const auto column = 1 + std::count_if(before.begin() + line_start, before.end(), [](char b) {
                          return (static_cast<unsigned char>(b) & 0xC0) != 0x80;
                        });
    char hex[16];
    std::snprintf(hex, sizeof hex, "U+%04X", static_cast<unsigned>(c));
    throw std::runtime_error(source + ":" + std::to_string(line) + ":" + std::to_string(column) +
                             ": the character " + hex +
                             " is only supported in string values and comments here (a bug of "
                             "the TOML library, toml++ 3.3)");
  };
  auto starts = [&](std::string_view s) { return text.substr(i).starts_with(s); };
  while (i < text.size()) {
    const char ch = text[i];
    if (ch == '\n') {
      if (state == State::comment) state = State::normal;
      if (state == State::normal && (brackets.empty() || brackets.back() != 'a')) previous = '\n';
      ++i;
      continue;
    }
    switch (state) {
      case State::comment:
        break;
      case State::normal:
        if (ch == '#') {
          state = State::comment;
        } else if (ch == '"' || ch == '\'') {
          value_string = at_value();
          const bool multi_line = starts(ch == '"' ? "\"\"\"" : "'''");
          state = ch == '"' ? (multi_line ? State::ml_basic : State::basic)
                            : (multi_line ? State::ml_literal : State::literal);
          if (multi_line) i += 2;
        } else if (ch == '[' || ch == '{') {
          brackets.push_back(ch == '{' ? 't' : at_value() ? 'a' : 'h');
          previous = ch;
        } else if (ch == ']' || ch == '}') {
          if (!brackets.empty()) brackets.pop_back();
          previous = ch;
        } else if (ch != ' ' && ch != '\t' && ch != '\r') {
          check(i);
          previous = ch;
        }
        break;
      case State::basic:
      case State::ml_basic:
        if (ch == '\\') {
          const std::size_t escaped = ++i;
          if (state == State::ml_basic)  // a line-ending backslash trims the whitespace after it
            while (i < text.size() && is_toml_blank(text[i])) ++i;
          check(i);
          if (i == escaped) ++i;  // skips the escaped character, not what follows a line break
          continue;
        } else if (ch == '"' && (state == State::basic || starts("\"\"\""))) {
          if (state == State::ml_basic)
            for (i += 2; i + 1 < text.size() && text[i + 1] == '"';) ++i;  // quotes ending it
          state = State::normal;
          previous = '"';
        } else if (!value_string) {
          check(i);
        }
        break;
      case State::literal:
      case State::ml_literal:
        if (ch == '\'' && (state == State::literal || starts("'''"))) {
          if (state == State::ml_literal)
            for (i += 2; i + 1 < text.size() && text[i + 1] == '\'';) ++i;
          state = State::normal;
          previous = '\'';
        } else if (!value_string) {
          check(i);
        }
        break;
    }
    ++i;
  }
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

  [[noreturn]] void fail(std::string_view key, const toml::node& node,
                         const std::string& what) const {
    throw std::invalid_argument(origin(key) + ": " + std::string(key) + " = " + show(node) + ": " +
                                what);
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
    const std::string key =
        eq == std::string::npos ? std::string{} : trim(assignment.substr(0, eq));
    if (key.empty())
      throw std::invalid_argument("command line: '" + assignment + "': overrides read key=value");
    const std::string text = trim(std::string_view(assignment).substr(eq + 1));
    toml::table parsed;
    const std::string line = "value = " + text;
    try {
      reject_toml_whitespace_bug(line, "--set");
      parsed = toml::parse(line, std::string_view{"--set"});
    } catch (const std::runtime_error&) {  // toml::parse_error, or a character toml++ trips on
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
      const std::string key =
          prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
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
  reject_toml_whitespace_bug(toml_text, source_name);
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
  if (!node)
    throw std::logic_error("RunConfig::choice: default of " + std::string(key) + " not allowed");
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
