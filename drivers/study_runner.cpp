#include "study_runner.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/progress.hpp"
#include "dynamic/protocols/run_guard.hpp"

namespace granstab::study {
namespace {

namespace fs = std::filesystem;

volatile std::sig_atomic_t stop_signal = 0;
extern "C" void on_stop_signal(int s) { stop_signal = s; }

std::string joined(const std::vector<std::string>& argv) {
  std::string s;
  for (const std::string& a : argv) s += a + "\n";
  return s;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The command's own checkpoint in a task's directory (a run stopped by a signal, a kill or a
// crash), or empty.
fs::path checkpoint_in(const fs::path& dir) {
  if (!fs::is_directory(dir)) return {};
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".checkpoint") return e.path();
  return {};
}

// Starts `exe argv...` in dir with stdout and stderr appended to dir/stdout.log and stderr.log.
// The child gets SIGTERM if the study dies (so a study killed with SIGKILL leaves no orphan
// running on; the command writes its checkpoint on SIGTERM).
pid_t start(const fs::path& exe, const std::vector<std::string>& argv, const fs::path& dir,
            int threads) {
  fs::create_directories(dir);
  const pid_t parent = getpid();
  const std::string out = (dir / "stdout.log").string(), err = (dir / "stderr.log").string();
  std::vector<std::string> args{exe.string()};
  args.insert(args.end(), argv.begin(), argv.end());
  std::vector<char*> c_args;
  for (std::string& a : args) c_args.push_back(a.data());
  c_args.push_back(nullptr);
  const std::string threads_text = std::to_string(threads);
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("study: fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(127);
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
    const int o = open(out.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (o < 0 || e < 0 || chdir(dir.c_str()) != 0) _exit(127);
    dup2(o, 1);
    dup2(e, 2);
    setenv("OMP_NUM_THREADS", threads_text.c_str(), 1);
    execv(c_args[0], c_args.data());
    _exit(127);
  }
  return pid;
}

enum class State { pending, running, done, failed, blocked, other_rank };

}  // namespace

std::vector<bool> select_points(
    const Plan& plan, const std::vector<std::pair<std::string, std::vector<std::string>>>& only) {
  std::vector<std::vector<bool>> allowed;  // per grid key, per value
  for (const GridKey& g : plan.grid) allowed.emplace_back(g.values.size(), true);
  for (const auto& [key, values] : only) {
    std::size_t k = 0;
    while (k < plan.grid.size() && plan.grid[k].name != key) ++k;
    if (k == plan.grid.size())
      throw std::invalid_argument("--only " + key + ": not a key of [grid] in " +
                                  plan.file.string());
    std::vector<bool> mask(plan.grid[k].values.size(), false);
    for (const std::string& v : values) {
      const auto& all = plan.grid[k].values;
      const auto it = std::find(all.begin(), all.end(), v);
      if (it == all.end())
        throw std::invalid_argument("--only " + key + "=" + v + ": not a value of grid." + key);
      mask[static_cast<std::size_t>(it - all.begin())] = true;
    }
    allowed[k] = mask;
  }
  std::vector<bool> selected(plan.tasks.size(), false);
  for (const Point& p : plan.points) {
    bool in = true;
    for (std::size_t k = 0; k < plan.grid.size(); ++k) in = in && allowed[k][p.value[k]];
    if (in)
      for (const std::size_t t : p.tasks) selected[t] = true;
  }
  return selected;
}

RunSummary run_plan(const Plan& plan, const RunOptions& o) {
  RunSummary summary;
  const std::size_t n = plan.tasks.size();
  std::vector<State> state(n, State::pending);
  // Deal the roots round robin; a task follows its root.
  std::map<std::size_t, std::size_t> root_ordinal;
  for (std::size_t t = 0; t < n; ++t)
    if (plan.tasks[t].root == t) root_ordinal.emplace(t, root_ordinal.size());
  for (std::size_t t = 0; t < n; ++t) {
    const Task& task = plan.tasks[t];
    if (root_ordinal.at(task.root) % static_cast<std::size_t>(o.ranks) !=
            static_cast<std::size_t>(o.rank) ||
        (!o.selected.empty() && !o.selected[t])) {
      state[t] = State::other_rank;
      continue;
    }
    ++summary.tasks;
    const fs::path done = task.directory / ".done";
    if (fs::exists(done)) {
      if (slurp(done) != joined(task.argv))
        throw std::runtime_error(
            task.directory.string() +
            ": done with another command line than the study file now gives it (see its .done); "
            "remove the directory to run it again");
      state[t] = State::done;
      ++summary.done_before;
    }
  }

  struct sigaction action {
  }, old_int{}, old_term{};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  stop_signal = 0;
  sigaction(SIGINT, &action, &old_int);
  sigaction(SIGTERM, &action, &old_term);
  struct Restore {
    struct sigaction *i, *t;
    ~Restore() {
      sigaction(SIGINT, i, nullptr);
      sigaction(SIGTERM, t, nullptr);
    }
  } restore{&old_int, &old_term};

  // The tasks of this run: those done before cost nothing, and counting them made the ETA of a
  // resumed study extrapolate from their instant "completion".
  Progress progress("study", static_cast<double>(summary.tasks - summary.done_before), !o.quiet,
                    10.0);
  std::map<pid_t, std::size_t> running;
  auto finished = [&] { return summary.ran + summary.failed + summary.blocked; };
  const std::string done_before =
      summary.done_before > 0 ? ", " + std::to_string(summary.done_before) + " done before" : "";
  while (true) {
    // Start every ready task, up to the job limit, in plan order.
    for (std::size_t t = 0;
         t < n && !stop_signal && running.size() < static_cast<std::size_t>(o.jobs); ++t) {
      if (state[t] != State::pending) continue;
      const Task& task = plan.tasks[t];
      bool ready = true;
      for (const std::size_t d : task.depends) {
        if (state[d] == State::failed || state[d] == State::blocked) {
          state[t] = State::blocked;
          ++summary.blocked;
          ready = false;
          break;
        }
        if (state[d] != State::done) ready = false;
      }
      if (!ready) continue;
      fs::remove(task.directory / ".failed");
      const fs::path checkpoint = checkpoint_in(task.directory);
      std::vector<std::string> argv = task.argv;
      // A checkpoint continues the command line that started it: refuse one of another.
      const fs::path started = task.directory / ".started";
      if (!checkpoint.empty() && fs::exists(started) && slurp(started) != joined(task.argv))
        throw std::runtime_error(task.directory.string() +
                                 ": its checkpoint is of another command line than the study file "
                                 "now gives it (see .started); remove the directory to start over");
      if (!checkpoint.empty())
        argv = {"resume", checkpoint.lexically_relative(task.directory).string()};
      fs::create_directories(task.directory);
      write_file_atomically(started, joined(task.argv));
      running.emplace(start(o.executable, argv, task.directory, o.threads_per_job), t);
      state[t] = State::running;
    }
    progress.update(
        static_cast<double>(finished()),
        std::to_string(running.size()) + " running, " + std::to_string(summary.failed) +
            " failed" + done_before);
    if (running.empty()) break;
    if (stop_signal) {
      int status = 0;
      for (const auto& [child, t] : running) kill(child, stop_signal);
      for (const auto& [child, t] : running) waitpid(child, &status, 0);
      const int s = stop_signal;
      throw protocols::Interrupted(
          s, "study stopped by signal " + std::to_string(s) +
                 "; the running commands wrote their checkpoints: run the same command again to "
                 "continue");
    }
    // Polled, so that a signal between the check above and a blocking wait is not missed.
    int status = 0;
    const pid_t pid = waitpid(-1, &status, WNOHANG);
    if (pid == 0 || (pid < 0 && errno == EINTR)) {
      usleep(50000);
      continue;
    }
    if (pid < 0) throw std::runtime_error(std::string("study: waitpid: ") + std::strerror(errno));
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const std::size_t t = it->second;
    running.erase(it);
    const Task& task = plan.tasks[t];
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      write_file_atomically(task.directory / ".done", joined(task.argv));
      state[t] = State::done;
      ++summary.ran;
    } else {
      const std::string how = WIFEXITED(status)
                                  ? "exit status " + std::to_string(WEXITSTATUS(status))
                                  : "signal " + std::to_string(WTERMSIG(status));
      write_file_atomically(task.directory / ".failed", how + "\n");
      state[t] = State::failed;
      ++summary.failed;
      if (!o.quiet)
        std::fprintf(stderr, "study: %s failed (%s; see its stderr.log)\n",
                     task.directory.string().c_str(), how.c_str());
    }
  }
  // Tasks behind a failure that the loop did not reach.
  for (std::size_t t = 0; t < n; ++t)
    if (state[t] == State::pending) {
      state[t] = State::blocked;
      ++summary.blocked;
    }
  return summary;
}

}  // namespace granstab::study
