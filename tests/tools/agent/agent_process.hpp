// SPDX-License-Identifier: MIT
/// @file Runs cmmcomp-agent as a child process for tests: its combined stdout/stderr is
/// collected, signals can be sent, and the exit status is waited for with a time limit.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace cmmcomp::test {

class AgentProcess {
 public:
  /// Starts `program` with `args`. Check running() / output() afterwards.
  AgentProcess(const std::string& program, const std::vector<std::string>& args) {
    int fds[2];
    if (pipe(fds) != 0) return;
    pid_ = fork();
    if (pid_ == 0) {
      dup2(fds[1], STDOUT_FILENO);
      dup2(fds[1], STDERR_FILENO);
      close(fds[0]);
      close(fds[1]);
      std::vector<char*> argv;
      argv.push_back(const_cast<char*>(program.c_str()));
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      execv(program.c_str(), argv.data());
      _exit(127);
    }
    close(fds[1]);
    fd_ = fds[0];
    fcntl(fd_, F_SETFL, fcntl(fd_, F_GETFL) | O_NONBLOCK);
  }
  ~AgentProcess() {
    if (pid_ > 0 && !exited_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    if (fd_ >= 0) close(fd_);
  }
  AgentProcess(const AgentProcess&) = delete;
  AgentProcess& operator=(const AgentProcess&) = delete;

  /// Everything the agent printed so far.
  const std::string& output() {
    drain(0);
    return output_;
  }

  /// Waits until the output contains `text` or the process ends or `timeout` passes.
  bool wait_for_output(const std::string& text, std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (output_.find(text) == std::string::npos) {
      if (std::chrono::steady_clock::now() > end) return false;
      if (!drain(50) && has_exited()) return output_.find(text) != std::string::npos;
    }
    return true;
  }

  /// The port the process printed right after `marker` (e.g. "listening on 127.0.0.1:"), once it
  /// printed it (waiting at most `timeout`); 0 when it did not.
  int port_after(const std::string& marker,
                 std::chrono::milliseconds timeout = std::chrono::milliseconds(10000)) {
    if (!wait_for_output(marker, timeout)) return 0;
    std::size_t at = output_.find(marker) + marker.size();
    int port = 0;
    while (at < output_.size() && output_[at] >= '0' && output_[at] <= '9') {
      port = port * 10 + (output_[at++] - '0');
    }
    return port;
  }

  void signal(int sig) const { kill(pid_, sig); }
  pid_t pid() const { return pid_; }

  /// Exit status after waiting at most `timeout`; -1 if still running, 128+N if killed by N.
  int wait_exit(std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!has_exited()) {
      if (std::chrono::steady_clock::now() > end) return -1;
      drain(20);
    }
    drain(0);
    return status_;
  }

 private:
  bool has_exited() {
    if (exited_) return true;
    int st = 0;
    if (waitpid(pid_, &st, WNOHANG) == pid_) {
      exited_ = true;
      status_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    }
    return exited_;
  }
  /// Reads what is available (waiting up to `ms`); true if anything was read.
  bool drain(int ms) {
    if (fd_ < 0) return false;
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, ms) <= 0) return false;
    char buf[4096];
    bool any = false;
    for (;;) {
      const ssize_t n = read(fd_, buf, sizeof buf);
      if (n <= 0) break;
      output_.append(buf, static_cast<std::size_t>(n));
      any = true;
    }
    return any;
  }

  pid_t pid_ = -1;
  int fd_ = -1;
  bool exited_ = false;
  int status_ = -1;
  std::string output_;
};

/// An agent serving Modbus TCP on a loopback port, started by start_modbus_agent.
struct RunningAgent {
  std::unique_ptr<AgentProcess> process;  ///< null when it could not be started
  int port = 0;
};

/// Starts `program` (cmmcomp-agent) with `--modbus tcp:127.0.0.1:PORT` plus `extra` on a free
/// port: ports are spread by pid and `salt` (so parallel tests rarely meet) and retried when
/// taken (libmodbus cannot bind port 0). Waits for its ready line. On failure `process` is null
/// and `*why` says what the agent printed.
inline RunningAgent start_modbus_agent(const std::string& program,
                                       const std::vector<std::string>& extra,
                                       int salt,
                                       std::string* why) {
  using namespace std::chrono_literals;
  for (int attempt = 0; attempt < 20; ++attempt) {
    const int port = 20000 + static_cast<int>((getpid() * 53 + salt * 997 + attempt * 131) % 25000);
    std::vector<std::string> args{"--modbus", "tcp:127.0.0.1:" + std::to_string(port)};
    args.insert(args.end(), extra.begin(), extra.end());
    auto p = std::make_unique<AgentProcess>(program, args);
    if (p->wait_for_output("listening on Modbus TCP", 10s)) return {std::move(p), port};
    if (p->output().find("in use") == std::string::npos) {
      *why = "agent did not start:\n" + p->output();
      return {};
    }
  }
  *why = "no free port";
  return {};
}

}  // namespace cmmcomp::test
