#pragma once
// The built granstab binary as a real child process (fork + exec) that a test can kill with a
// real signal at chosen moments: after it has written its k-th checkpoint (seen as a new
// modification time of the checkpoint file, which every atomic rename gives).
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "run_granstab.hpp"

namespace granstab::testing {

class Child {
 public:
  // Runs the built granstab (granstab_exe()) with args in dir, one OpenMP thread, stderr to
  // dir/../stderr.log.
  Child(const std::filesystem::path& dir, const std::vector<std::string>& args, int threads = 1) {
    const std::string log = (dir.parent_path() / "stderr.log").string();
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      if (::chdir(dir.c_str()) != 0) ::_exit(126);
      ::setenv("OMP_NUM_THREADS", std::to_string(threads).c_str(), 1);
      const int null = ::open("/dev/null", O_WRONLY);
      const int err = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(null, 1);
      ::dup2(err, 2);
      std::vector<char*> argv;
      std::string exe = granstab_exe();
      argv.push_back(exe.data());
      std::vector<std::string> copy = args;
      for (auto& a : copy) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(exe.c_str(), argv.data());
      ::_exit(127);
    }
  }
  ~Child() {
    if (pid_ > 0 && !reaped_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  // Waits until `checkpoints` new versions of the file have appeared, then sends `signal`.
  // Returns false (and sends nothing) if the child exited first.
  bool signal_after(const std::filesystem::path& checkpoint, int checkpoints, int signal) {
    int seen = 0;
    struct timespec last {};
    struct stat initial {};
    if (::stat(checkpoint.c_str(), &initial) == 0) last = initial.st_mtim;  // an older one
    for (;;) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        reaped_ = true;
        status_ = status;
        return false;
      }
      struct stat st {};
      if (::stat(checkpoint.c_str(), &st) == 0 &&
          (st.st_mtim.tv_sec != last.tv_sec || st.st_mtim.tv_nsec != last.tv_nsec)) {
        last = st.st_mtim;
        if (++seen >= checkpoints) {
          ::kill(pid_, signal);
          return true;
        }
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  }

  // Sends `signal` if the child is still running; false if it had exited.
  bool signal_if_running(int signal) {
    int status = 0;
    if (reaped_ || ::waitpid(pid_, &status, WNOHANG) == pid_) {
      if (!reaped_) status_ = status;
      reaped_ = true;
      return false;
    }
    return ::kill(pid_, signal) == 0;
  }

  // Exit code, or 128 + signal when killed by a signal.
  int wait() {
    if (!reaped_) {
      ::waitpid(pid_, &status_, 0);
      reaped_ = true;
    }
    return WIFEXITED(status_) ? WEXITSTATUS(status_) : 128 + WTERMSIG(status_);
  }

 private:
  pid_t pid_ = -1;
  bool reaped_ = false;
  int status_ = 0;
};

}  // namespace granstab::testing
