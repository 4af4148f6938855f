#include "run_guard.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>

namespace granstab::protocols {
namespace {

volatile std::sig_atomic_t caught = 0;

extern "C" void on_signal(int signal) { caught = signal; }

std::string slurp(const std::filesystem::path& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open " + what);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

GuardSettings read_guard_settings(RunConfig& rc, const std::filesystem::path& default_checkpoint) {
  GuardSettings s;
  s.checkpoint = rc.path("checkpoint.path").value_or(default_checkpoint);
  s.every_steps = static_cast<std::uint64_t>(
      rc.integer("checkpoint.every_steps", 0, 0, std::numeric_limits<std::int64_t>::max()));
  s.every_seconds = rc.number("checkpoint.every_seconds", s.every_seconds, 0.0, 1e9);
  s.sanity.max_overlap_fraction =
      rc.number("sanity.max_overlap_fraction", s.sanity.max_overlap_fraction, 1e-6, 2.0);
  s.sanity.max_kinetic_energy =
      rc.number("sanity.max_kinetic_energy", s.sanity.max_kinetic_energy, 1e-12, 1e12);
  s.sanity_every_steps = static_cast<std::uint64_t>(
      rc.integer("sanity.every_steps", static_cast<std::int64_t>(s.sanity_every_steps), 1,
                 std::numeric_limits<std::int64_t>::max()));
  return s;
}

Invocation Invocation::start(std::string command, std::string settings,
                             std::vector<std::string> overrides) {
  Invocation inv;
  inv.command = std::move(command);
  inv.settings = std::move(settings);
  {
    std::ifstream in(inv.settings, std::ios::binary);
    if (!in) throw std::runtime_error(inv.settings + ": cannot open settings file");
    std::ostringstream s;
    s << in.rdbuf();
    inv.settings_text = s.str();
  }
  inv.overrides = std::move(overrides);
  inv.working_directory = std::filesystem::current_path();
  remove_stale_temporaries(inv.named_outputs());
  return inv;
}

Invocation Invocation::from_arguments(std::string command, std::vector<std::string> arguments,
                                      std::vector<std::string> overrides) {
  Invocation inv;
  inv.command = std::move(command);
  inv.arguments = std::move(arguments);
  inv.overrides = std::move(overrides);
  inv.working_directory = std::filesystem::current_path();
  return inv;
}

RunConfig Invocation::settings_config() const {
  if (settings.empty()) return RunConfig::from_string("", "command line", overrides);
  const std::filesystem::path file(settings);
  return RunConfig::from_string(settings_text, file.string(), overrides, file.parent_path());
}

void Invocation::add_resume_overrides(const std::vector<std::string>& extra) {
  const auto& allowed = resumable_settings();
  for (const std::string& assignment : extra) {
    const auto eq = assignment.find('=');
    std::string key = assignment.substr(0, eq);
    key.erase(0, key.find_first_not_of(" \t"));
    key.erase(key.find_last_not_of(" \t") + 1);
    if (eq == std::string::npos ||
        std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string list;
      for (const auto& k : allowed) list += (list.empty() ? "" : ", ") + k;
      throw std::invalid_argument(
          "resume: --set " + assignment + ": " +
          (eq == std::string::npos ? std::string("overrides read key=value")
                                   : key + " cannot change in the middle of a run (the state "
                                           "in the checkpoint depends on it; start a new run)") +
          "; resume may change only " + list);
    }
    overrides.push_back(assignment);
  }
}

void Invocation::put(Checkpoint& c) const {
  c.set("run.command", command);
  c.set("run.settings", settings);
  c.set("run.settings_text", settings_text);
  c.set_count("run.overrides", overrides.size());
  for (std::size_t k = 0; k < overrides.size(); ++k) {
    c.set("run.override_" + std::to_string(k), overrides[k]);
  }
  c.set("run.working_directory", working_directory.string());
  if (!arguments.empty()) {
    c.set_count("run.arguments", arguments.size());
    for (std::size_t k = 0; k < arguments.size(); ++k) {
      c.set("run.argument_" + std::to_string(k), arguments[k]);
    }
  }
}

Invocation Invocation::get(const Checkpoint& c) {
  Invocation inv;
  inv.command = c.text("run.command");
  inv.settings = c.text("run.settings");
  inv.settings_text = c.text("run.settings_text");
  const std::uint64_t n = c.count("run.overrides");
  if (n > 10000) throw std::runtime_error(c.source_name() + ": entry run.overrides: too many");
  for (std::uint64_t k = 0; k < n; ++k)
    inv.overrides.push_back(c.text("run.override_" + std::to_string(k)));
  inv.working_directory = c.text("run.working_directory");
  const std::uint64_t n_arguments = c.has("run.arguments") ? c.count("run.arguments") : 0;
  if (n_arguments > 10000) {
    throw std::runtime_error(c.source_name() + ": entry run.arguments: too many");
  }
  for (std::uint64_t k = 0; k < n_arguments; ++k) {
    inv.arguments.push_back(c.text("run.argument_" + std::to_string(k)));
  }
  return inv;
}

std::vector<std::filesystem::path> Invocation::named_outputs() const {
  std::vector<std::filesystem::path> paths;
  if (settings.empty()) return paths;
  try {
    RunConfig rc = settings_config();
    for (const char* key : {"output.csv", "output.sample", "output.summary", "output.hold_sample",
                            "output.save_prefix", "output.vtk", "checkpoint.path"}) {
      if (!rc.contains(key)) continue;
      if (const auto p = rc.path(key)) paths.push_back(*p);
    }
  } catch (const std::exception&) {
    paths.clear();  // unreadable settings: the command says why
  }
  return paths;
}

namespace {

// ".NAME.tmp-XXXXXX" (mkstemp's six characters): NAME, or "" when it is not such a name.
std::string temporary_of(const std::string& file) {
  constexpr std::string_view tag = ".tmp-";
  if (file.size() < 1 + tag.size() + 6 || file[0] != '.') return {};
  const std::size_t at = file.size() - 6 - tag.size();
  if (file.compare(at, tag.size(), tag) != 0) return {};
  for (std::size_t k = file.size() - 6; k < file.size(); ++k) {
    if (!std::isalnum(static_cast<unsigned char>(file[k]))) return {};
  }
  return file.substr(1, at - 1);
}

}  // namespace

std::size_t remove_stale_temporaries(const std::vector<std::filesystem::path>& outputs) {
  std::size_t removed = 0;
  for (const std::filesystem::path& output : outputs) {
    const std::filesystem::path dir = output.parent_path().empty() ? "." : output.parent_path();
    const std::string stem = output.stem().string();
    if (stem.empty()) continue;
    std::error_code error;
    std::filesystem::directory_iterator it(dir, error), end;
    if (error) continue;  // no directory yet: nothing stale in it
    std::vector<std::filesystem::path> stale;
    for (; !error && it != end; it.increment(error)) {
      const std::string name = temporary_of(it->path().filename().string());
      if (name == stem || name.starts_with(stem + ".") || name.starts_with(stem + "_")) {
        stale.push_back(it->path());
      }
    }
    for (const auto& p : stale) removed += std::filesystem::remove(p, error) ? 1 : 0;
  }
  return removed;
}

std::string file_checksum(const std::filesystem::path& path) {
  return std::to_string(fnv1a64(slurp(path, "input file")));
}

RunGuard::RunGuard(GuardSettings settings, std::string label)
    : settings_(std::move(settings)),
      label_(std::move(label)),
      last_written_time_(std::chrono::steady_clock::now()) {
  caught = 0;
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  sigaction(SIGINT, &action, &old_int_);
  sigaction(SIGTERM, &action, &old_term_);
}

RunGuard::~RunGuard() {
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

int RunGuard::caught_signal() { return caught; }

void RunGuard::write(const Checkpoint& checkpoint) {
  if (flush_) flush_();
  checkpoint.write(settings_.checkpoint);
  ++written_;
}

void RunGuard::sanity(const Engine& engine) {
  const std::uint64_t step = engine.step_count();
  if (last_checked_step_ == step) return;
  engine.export_to(exported_);
  const auto blow_up = dynamic::find_blow_up(engine, exported_, settings_.sanity);
  if (!blow_up) {
    last_checked_step_ = step;
    return;
  }
  std::string message = label_ + ": the run blew up at " + *blow_up + "; ";
  if (last_sane_) {
    write(*last_sane_);
    message += "the last sane state (step " + std::to_string(*last_sane_step_) +
               ") is in the checkpoint " + settings_.checkpoint.string() +
               "; the outputs hold only states that passed the checks";
  } else {
    message += "no sane state was saved";
  }
  throw BlewUp(message);
}

void RunGuard::check(const Engine& engine) { sanity(engine); }

void RunGuard::safe_point(const Engine& engine, const Builder& build) {
  const std::uint64_t step = engine.step_count();
  const int signal = caught;
  const bool sanity_due =
      !last_checked_step_ || step - *last_checked_step_ >= settings_.sanity_every_steps;
  if (sanity_due) sanity(engine);
  const auto now = std::chrono::steady_clock::now();
  const bool due =
      signal != 0 ||
      (settings_.every_steps > 0 && last_written_step_ &&
       step - *last_written_step_ >= settings_.every_steps) ||
      (settings_.every_seconds > 0.0 &&
       std::chrono::duration<double>(now - last_written_time_).count() >= settings_.every_seconds);
  if (!last_written_step_) last_written_step_ = step;
  if (!sanity_due && !due) return;
  sanity(engine);  // a checkpoint never holds a state that was not checked
  last_sane_ = build();
  last_sane_step_ = step;
  if (!due) return;
  write(*last_sane_);
  last_written_step_ = step;
  last_written_time_ = now;
  if (signal != 0) {
    const char* name = signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "a signal";
    throw Interrupted(signal, label_ + ": stopped by " + std::string(name) + " at step " +
                                  std::to_string(step) + "; continue with: granstab resume " +
                                  settings_.checkpoint.string());
  }
}

bool RunGuard::wants(const Engine& engine) const {
  const std::uint64_t step = engine.step_count();
  return caught != 0 || !last_checked_step_ ||
         step - *last_checked_step_ >= settings_.sanity_every_steps || !last_written_step_ ||
         (settings_.every_steps > 0 && step - *last_written_step_ >= settings_.every_steps) ||
         (settings_.every_seconds > 0.0 &&
          std::chrono::duration<double>(std::chrono::steady_clock::now() - last_written_time_)
                  .count() >= settings_.every_seconds);
}

void RunGuard::finish() {
  std::error_code ignored;
  if (written_ > 0) std::filesystem::remove(settings_.checkpoint, ignored);
}

void restore_csv(CsvWriter& csv, std::uint64_t bytes) {
  const std::string name = csv.path().string();
  const std::string all = slurp(csv.path(), "the CSV output to resume");
  if (all.size() < bytes) {
    throw std::runtime_error(name + ": " + std::to_string(all.size()) + " bytes, fewer than the " +
                             std::to_string(bytes) + " the checkpoint recorded (was it changed?)");
  }
  const std::string_view kept(all.data(), bytes);
  const std::size_t header_end = kept.find('\n');
  if (header_end == std::string_view::npos || kept.back() != '\n' ||
      kept.substr(0, header_end + 1) != std::string_view(csv.text())) {
    throw std::runtime_error(name + ": not the CSV the checkpoint recorded (header or row end)");
  }
  std::vector<double> values;
  std::size_t pos = header_end + 1;
  while (pos < kept.size()) {
    const std::size_t end = kept.find('\n', pos);
    values.clear();
    std::size_t field = pos;
    for (;;) {
      std::size_t comma = kept.find(',', field);
      if (comma == std::string_view::npos || comma > end) comma = end;
      double v = 0.0;
      const auto r = std::from_chars(kept.data() + field, kept.data() + comma, v);
      if (r.ec != std::errc() || r.ptr != kept.data() + comma) {
        throw std::runtime_error(name + ": unreadable number in a row before the checkpoint");
      }
      values.push_back(v);
      if (comma == end) break;
      field = comma + 1;
    }
    csv.row(values);
    pos = end + 1;
  }
  if (csv.text() != kept) {
    throw std::runtime_error(name + ": its rows do not read back to the same text");
  }
  csv.flush();
}

}  // namespace granstab::protocols
