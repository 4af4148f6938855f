#include "study_plan.hpp"

#include <algorithm>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <toml++/toml.h>

#include "common/io/json_text.hpp"

namespace granstab::study {
namespace {

namespace fs = std::filesystem;

// The commands a step may run, and the outputs the runner names for them (each task writes into
// its own directory under fixed names, so later steps and the report know where to look).
struct CommandRule {
  const char* command;
  bool takes_settings;                // a settings file is its first argument
  std::vector<std::string> forced;    // --set key=value the runner adds
  std::vector<std::string> out_flag;  // arguments the runner adds
};
const std::vector<CommandRule>& command_rules() {
  static const std::vector<CommandRule> rules = {
      {"prepare",
       true,
       {"output.sample=\"sample.granstab\"", "output.summary=\"summary.json\""},
       {}},
      {"biaxial", true, {"output.csv=\"curve.csv\"", "output.summary=\"summary.json\""}, {}},
      {"q1", false, {}, {"--out", "."}},
      {"compare", false, {}, {"--out", "."}},
      {"sic", false, {}, {"--out", "."}},
  };
  return rules;
}

class Reader {
 public:
  explicit Reader(fs::path file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const toml::node* node, const std::string& key,
                         const std::string& what) const {
    std::ostringstream m;
    m << file_.string();
    if (node && node->source().begin.line > 0) m << ":" << node->source().begin.line;
    m << ": " << key << ": " << what;
    throw std::invalid_argument(m.str());
  }

  // A scalar as the text a command line takes: strings as they are, numbers in shortest form.
  std::string scalar_text(const toml::node& n, const std::string& key) const {
    if (auto s = n.as_string()) return s->get();
    if (auto i = n.as_integer()) return std::to_string(i->get());
    if (auto d = n.as_floating_point()) return json_number(d->get());
    if (auto b = n.as_boolean()) return b->get() ? "true" : "false";
    fail(&n, key, "expected a string, a number or a boolean");
  }

  const fs::path& file() const { return file_; }

 private:
  fs::path file_;
};

bool safe_for_a_path(const std::string& v) {
  return !v.empty() && v != "." && v != ".." && std::none_of(v.begin(), v.end(), [](char c) {
    return c == '/' || c == '\\' || c == ' ' || c == '\t' || c == '\n' || c == '{' || c == '}';
  });
}

// Replaces every {name} in text by vars[name]; an unknown name is an error naming `key`.
std::string expand(const std::string& text, const std::map<std::string, std::string>& vars,
                   const std::function<void(const std::string&)>& unknown) {
  std::string out;
  std::size_t at = 0;
  while (true) {
    const std::size_t open = text.find('{', at);
    if (open == std::string::npos) break;
    const std::size_t close = text.find('}', open);
    if (close == std::string::npos) break;
    out += text.substr(at, open - at);
    const std::string name = text.substr(open + 1, close - open - 1);
    const auto it = vars.find(name);
    if (it == vars.end()) unknown(name);
    out += it->second;
    at = close + 1;
  }
  return out + text.substr(at);
}

void flatten(const Reader& r, const toml::table& t, const std::string& prefix,
             std::vector<std::string>& out, const std::string& key) {
  for (const auto& [k, v] : t) {
    const std::string name =
        prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (auto sub = v.as_table()) {
      flatten(r, *sub, name, out, key);
    } else {
      std::string value;
      if (auto s = v.as_string()) {
        value = s->get();
      } else if (v.is_array()) {
        std::ostringstream text;
        text << *v.as_array();
        value = text.str();
      } else {
        value = r.scalar_text(v, key + "." + name);
      }
      out.push_back(name + "=" + value);
    }
  }
}

std::vector<std::string> string_array(const Reader& r, const toml::node& n,
                                      const std::string& key) {
  const toml::array* a = n.as_array();
  if (!a) r.fail(&n, key, "expected an array");
  std::vector<std::string> out;
  for (const auto& e : *a) out.push_back(r.scalar_text(e, key));
  return out;
}

// Every key of `earlier` is a key of `step`: one task of `earlier` per task of `step`.
bool refines(const Step& step, const Step& earlier) {
  return std::all_of(earlier.vary.begin(), earlier.vary.end(), [&](const std::string& g) {
    return std::find(step.vary.begin(), step.vary.end(), g) != step.vary.end();
  });
}

}  // namespace

Plan read_plan(const fs::path& file_in) {
  Plan plan;
  plan.file = fs::absolute(file_in);
  const Reader r(file_in);
  toml::table doc;
  try {
    doc = toml::parse_file(file_in.string());
  } catch (const toml::parse_error& e) {
    std::ostringstream m;
    m << file_in.string() << ":" << e.source().begin.line << ":" << e.source().begin.column << ": "
      << e.description();
    throw std::invalid_argument(m.str());
  }
  const fs::path base = plan.file.parent_path();
  for (const auto& [k, v] : doc) {
    const std::string key(k.str());
    if (key != "study" && key != "grid" && key != "step")
      r.fail(&v, key, "unknown table (expected [study], [grid], [[step]])");
  }

  // [study]
  plan.out = base / (plan.file.stem().string() + "-out");
  if (const auto* study = doc["study"].as_table()) {
    for (const auto& [k, v] : *study) {
      const std::string key = "study." + std::string(k.str());
      if (k.str() == "out") {
        const auto* s = v.as_string();
        if (!s || s->get().empty()) r.fail(&v, key, "expected a directory name");
        plan.out = fs::absolute(base / s->get()).lexically_normal();
      } else {
        r.fail(&v, key, "unknown key (expected out)");
      }
    }
  } else if (doc.contains("study")) {
    r.fail(doc.get("study"), "study", "expected a table");
  }

  // [grid]: keys in file order
  if (const auto* grid = doc["grid"].as_table()) {
    std::vector<std::pair<std::size_t, GridKey>> keys;
    for (const auto& [k, v] : *grid) {
      const std::string key = "grid." + std::string(k.str());
      GridKey g{std::string(k.str()), string_array(r, v, key)};
      if (g.values.empty()) r.fail(&v, key, "no values");
      if (!safe_for_a_path(g.name))
        r.fail(&v, key, "a key must not contain '/', '{', '}' or spaces");
      std::set<std::string> seen;
      for (const std::string& value : g.values) {
        if (!safe_for_a_path(value))
          r.fail(&v, key, "value \"" + value + "\" cannot name a directory ('/', spaces, braces)");
        if (!seen.insert(value).second) r.fail(&v, key, "value " + value + " given twice");
      }
      keys.emplace_back(v.source().begin.line * 100000 + v.source().begin.column, std::move(g));
    }
    std::stable_sort(keys.begin(), keys.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    for (auto& [line, g] : keys) plan.grid.push_back(std::move(g));
  } else if (doc.contains("grid")) {
    r.fail(doc.get("grid"), "grid", "expected a table");
  }
  auto grid_index = [&](const std::string& name) -> std::ptrdiff_t {
    for (std::size_t k = 0; k < plan.grid.size(); ++k)
      if (plan.grid[k].name == name) return static_cast<std::ptrdiff_t>(k);
    return -1;
  };

  // [[step]]
  const toml::array* steps = doc["step"].as_array();
  if (!steps || steps->empty())
    r.fail(doc.get("step"), "step", "no [[step]] (the pipeline of a point)");
  std::vector<const toml::table*> step_tables;
  for (std::size_t s = 0; s < steps->size(); ++s) {
    const toml::node& node = *steps->get(s);
    const std::string prefix = "step[" + std::to_string(s + 1) + "]";
    const toml::table* t = node.as_table();
    if (!t) r.fail(&node, prefix, "expected a table ([[step]])");
    step_tables.push_back(t);
    Step step;
    const CommandRule* rule = nullptr;
    bool has_vary = false;
    for (const auto& [k, v] : *t) {
      const std::string key = prefix + "." + std::string(k.str());
      if (k.str() == "command") {
        const auto* s = v.as_string();
        for (const CommandRule& c : command_rules())
          if (s && s->get() == c.command) rule = &c;
        if (!rule) r.fail(&v, key, "expected one of prepare, biaxial, q1, compare, sic");
        step.command = s->get();
      } else if (k.str() == "name") {
        const auto* s = v.as_string();
        if (!s || !safe_for_a_path(s->get()))
          r.fail(&v, key, "expected a name usable as a directory");
        step.name = s->get();
      } else if (k.str() == "vary") {
        step.vary = string_array(r, v, key);
        has_vary = true;
        for (const std::string& g : step.vary)
          if (grid_index(g) < 0) r.fail(&v, key, g + " is not a key of [grid]");
      } else if (k.str() == "settings") {
        const auto* s = v.as_string();
        if (!s) r.fail(&v, key, "expected a path (relative to the study file)");
        step.settings = (base / s->get()).lexically_normal();
        if (!fs::is_regular_file(step.settings))
          r.fail(&v, key, step.settings.string() + ": no such file");
      } else if (k.str() == "set") {
        const auto* st = v.as_table();
        if (!st) r.fail(&v, key, "expected a table of settings, e.g. { \"sample.n\" = \"{n}\" }");
        flatten(r, *st, "", step.set, key);
      } else if (k.str() == "arguments") {
        step.arguments = string_array(r, v, key);
      } else {
        r.fail(&v, key, "unknown key (expected command, name, vary, settings, set, arguments)");
      }
    }
    if (!rule) r.fail(t, prefix + ".command", "missing");
    if (step.name.empty()) step.name = step.command;
    for (const Step& earlier : plan.steps)
      if (earlier.name == step.name)
        r.fail(t, prefix + ".name", "\"" + step.name + "\" is used by an earlier step");
    if (grid_index(step.name) >= 0 || step.name == "study_dir")
      r.fail(t, prefix + ".name", "\"" + step.name + "\" is a grid key or study_dir");
    if (rule->takes_settings && step.settings.empty())
      r.fail(t, prefix + ".settings", "missing (" + step.command + " reads a settings file)");
    if (!rule->takes_settings && !step.settings.empty())
      r.fail(t, prefix + ".settings", step.command + " takes no settings file: use arguments");
    if (!rule->takes_settings && !step.set.empty())
      r.fail(t, prefix + ".set", step.command + " takes options: use arguments");
    for (const std::string& f : rule->forced)
      for (const std::string& s : step.set)
        if (s.substr(0, s.find('=')) == f.substr(0, f.find('=')))
          r.fail(t, prefix + ".set", s.substr(0, s.find('=')) + " is set by the study (" + f + ")");
    for (const std::string& a : step.arguments)
      if (a == "--out" || a.starts_with("--out="))
        r.fail(t, prefix + ".arguments", "--out is set by the study (the step's directory)");
    if (!has_vary)
      for (const GridKey& g : plan.grid) step.vary.push_back(g.name);
    // In grid order, so that directory names do not depend on how vary was written.
    std::sort(step.vary.begin(), step.vary.end(), [&](const std::string& a, const std::string& b) {
      return grid_index(a) < grid_index(b);
    });
    if (!plan.steps.empty())
      for (const std::string& g : plan.steps.front().vary)
        if (std::find(step.vary.begin(), step.vary.end(), g) == step.vary.end())
          r.fail(t, prefix + ".vary",
                 "must include " + g + ", a key of the first step (every task follows one " +
                     plan.steps.front().command + " task)");
    plan.steps.push_back(std::move(step));
  }

  // Expand: one task per step and per combination of its vary values.
  const std::size_t n_keys = plan.grid.size();
  std::size_t n_points = 1;
  for (const GridKey& g : plan.grid) n_points *= g.values.size();
  std::vector<std::map<std::vector<std::size_t>, std::size_t>> task_of(plan.steps.size());
  for (std::size_t p = 0; p < n_points; ++p) {
    Point point;
    point.value.resize(n_keys);
    std::size_t rest = p;
    for (std::size_t k = n_keys; k-- > 0;) {
      point.value[k] = rest % plan.grid[k].values.size();
      rest /= plan.grid[k].values.size();
    }
    plan.points.push_back(std::move(point));
  }
  for (std::size_t s = 0; s < plan.steps.size(); ++s) {
    const Step& step = plan.steps[s];
    const CommandRule& rule =
        *std::find_if(command_rules().begin(), command_rules().end(),
                      [&](const CommandRule& c) { return step.command == c.command; });
    const std::string prefix = "step[" + std::to_string(s + 1) + "]";
    for (Point& point : plan.points) {
      std::vector<std::size_t> value;
      std::string dir_name;
      std::map<std::string, std::string> vars{{"study_dir", base.string()}};
      for (const std::string& g : step.vary) {
        const auto k = static_cast<std::size_t>(grid_index(g));
        value.push_back(point.value[k]);
        const std::string& v = plan.grid[k].values[point.value[k]];
        dir_name += (dir_name.empty() ? "" : "_") + g + "-" + v;
        vars[g] = v;
      }
      const auto [it, inserted] = task_of[s].emplace(value, plan.tasks.size());
      if (inserted) {
        Task task;
        task.step = s;
        task.value = value;
        task.directory = plan.out / step.name / (dir_name.empty() ? "all" : dir_name);
        // It runs after the latest earlier step that it refines (whose keys it all has): the
        // pipeline's order, except that a step on fewer keys (a sibling) is not waited for.
        if (s > 0) {
          std::size_t before = 0;
          for (std::size_t e = s; e-- > 0;)
            if (refines(step, plan.steps[e])) {
              before = point.tasks[e];
              break;
            }
          task.depends.push_back(before);
          task.root = plan.tasks[before].root;
        } else {
          task.root = plan.tasks.size();
        }
        // {STEP}: the directories of the earlier steps it refines (one task each).
        for (std::size_t e = 0; e < s; ++e)
          if (refines(step, plan.steps[e]))
            vars[plan.steps[e].name] = plan.tasks[point.tasks[e]].directory.string();
        const toml::table* t = step_tables[s];
        auto unknown = [&](const std::string& key) {
          return [&, key](const std::string& name) {
            const bool is_grid = grid_index(name) >= 0;
            r.fail(t, prefix + "." + key,
                   "{" + name + "}: " +
                       (is_grid ? "a grid key not in this step's vary"
                                : "neither a grid key nor an earlier step whose keys this step "
                                  "has nor study_dir"));
          };
        };
        task.argv.push_back(step.command);
        if (rule.takes_settings) task.argv.push_back(step.settings.string());
        for (const std::string& a : step.arguments)
          task.argv.push_back(expand(a, vars, unknown("arguments")));
        for (const std::string& f : rule.forced) task.argv.insert(task.argv.end(), {"--set", f});
        for (const std::string& a : step.set)
          task.argv.insert(task.argv.end(), {"--set", expand(a, vars, unknown("set"))});
        task.argv.insert(task.argv.end(), rule.out_flag.begin(), rule.out_flag.end());
        plan.tasks.push_back(std::move(task));
      }
      point.tasks.push_back(it->second);
    }
  }
  return plan;
}

std::string plan_json(const Plan& plan) {
  std::ostringstream j;
  j << "{\n  \"study\": " << json_string(plan.file.string())
    << ",\n  \"out\": " << json_string(plan.out.string()) << ",\n  \"grid\": {";
  for (std::size_t k = 0; k < plan.grid.size(); ++k) {
    j << (k ? ", " : "") << json_string(plan.grid[k].name) << ": [";
    for (std::size_t v = 0; v < plan.grid[k].values.size(); ++v)
      j << (v ? ", " : "") << json_string(plan.grid[k].values[v]);
    j << "]";
  }
  j << "},\n  \"steps\": [";
  for (std::size_t s = 0; s < plan.steps.size(); ++s) {
    j << (s ? ", " : "") << "{\"name\": " << json_string(plan.steps[s].name)
      << ", \"command\": " << json_string(plan.steps[s].command) << "}";
  }
  j << "],\n  \"points\": [\n";
  for (std::size_t p = 0; p < plan.points.size(); ++p) {
    const Point& point = plan.points[p];
    j << "    {\"values\": {";
    for (std::size_t k = 0; k < plan.grid.size(); ++k)
      j << (k ? ", " : "") << json_string(plan.grid[k].name) << ": "
        << json_string(plan.grid[k].values[point.value[k]]);
    j << "}, \"steps\": {";
    for (std::size_t s = 0; s < point.tasks.size(); ++s) {
      const Task& t = plan.tasks[point.tasks[s]];
      j << (s ? ", " : "") << json_string(plan.steps[s].name) << ": "
        << json_string(fs::relative(t.directory, plan.out).string());
    }
    j << "}}" << (p + 1 < plan.points.size() ? "," : "") << "\n";
  }
  j << "  ]\n}\n";
  return j.str();
}

}  // namespace granstab::study
