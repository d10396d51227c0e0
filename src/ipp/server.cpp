// SPDX-License-Identifier: MIT
/// @file The I++ DME socket server (server.hpp).
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cmmcomp/ipp/line.hpp>
#include <cmmcomp/ipp/server.hpp>
#include <cmmcomp/ipp/socket.hpp>
#include <optional>
#include <vector>

namespace cmmcomp::ipp {

using net::set_nonblocking;

struct Server::Impl {
  Session& session;
  ServerOptions options;
  int listen_fd = -1;
  int wake[2] = {-1, -1};
  std::uint16_t port = 0;
  // The client.
  int fd = -1;
  std::string in, out;
  bool closing = false;  ///< send what waits, then close
  net::Clock::time_point last_sent;
  std::optional<Executed> current;
  net::Clock::time_point deadline;

  Impl(Session& s, const ServerOptions& o) : session(s), options(o) {}

  ~Impl() {
    if (fd >= 0) ::close(fd);
    if (listen_fd >= 0) ::close(listen_fd);
    for (int w : wake) {
      if (w >= 0) ::close(w);
    }
  }

  void log(const std::string& s) const {
    if (options.log) options.log(s);
  }

  void listen() {
    const net::Listener l = net::listen_tcp(options.host, options.port, "I++ server");
    listen_fd = l.fd;
    port = l.port;
    if (::pipe2(wake, O_NONBLOCK | O_CLOEXEC) != 0) {
      throw Error("I++ server: pipe: " + std::string(std::strerror(errno)));
    }
  }

  void queue_lines(std::vector<std::string>& lines) {
    // The send timeout counts from when answers start to wait, not from the last send.
    if (out.empty() && !lines.empty()) last_sent = net::Clock::now();
    for (const std::string& l : lines) {
      out += l;
      out += "\r\n";
    }
    lines.clear();
  }

  void drop(const char* why) {
    log(std::string("client dropped: ") + why);
    if (current) {
      std::vector<std::string> discard;
      session.finish(std::move(*current), discard);
      current.reset();
    }
    session.disconnected();
    ::close(fd);
    fd = -1;
    in.clear();
    out.clear();
    closing = false;
  }

  void accept_client() {
    const int c = ::accept4(listen_fd, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
    if (c < 0) return;
    if (fd >= 0) {
      // A client that has just left (a proxy or a program reconnecting at once) is not an
      // active session: its end may wait behind this connection in the same poll round.
      pollfd q{fd, POLLRDHUP, 0};
      if (::poll(&q, 1, 0) > 0 && (q.revents & (POLLRDHUP | POLLHUP | POLLERR))) {
        drop("it closed the connection");
      }
    }
    if (fd >= 0) {
      const std::string line =
          error_line("E0000", ErrorCode::kBadContext, "", "another client session is active") +
          "\r\n";
      const ssize_t ignored = ::send(c, line.data(), line.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
      (void)ignored;
      ::close(c);
      log("second connection refused");
      return;
    }
    fd = c;
    last_sent = net::Clock::now();
    log("client connected");
  }

  void read_client() {
    char buffer[4096];
    const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
      drop(n == 0 ? "it closed the connection" : "receive error");
      return;
    }
    if (n < 0) return;
    std::vector<std::string> answers;
    std::size_t start = 0;
    for (ssize_t i = 0; i < n; ++i) {
      if (buffer[i] != '\n') continue;
      in.append(buffer + start, static_cast<std::size_t>(i) - start);
      start = static_cast<std::size_t>(i) + 1;
      session.receive(in, answers);
      in.clear();
      // Each line runs before the next is read, as if it had come alone: a burst of commands
      // fills the queue only while a real-time move runs.
      if (!closing) run_work(answers);
    }
    in.append(buffer + start, static_cast<std::size_t>(n) - start);
    if (in.size() > kMaxLineBytes + 1) {
      answers.push_back(error_line("E0000",
                                   ErrorCode::kProtocolError,
                                   in.substr(0, 40),
                                   "a line longer than 1024 bytes: closing the connection"));
      closing = true;
      in.clear();
    }
    queue_lines(answers);
  }

  void write_client() {
    const ssize_t n = ::send(fd, out.data(), out.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) {
      out.erase(0, static_cast<std::size_t>(n));
      last_sent = net::Clock::now();
    } else if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
      drop("send error");
    }
  }

  /// Starts what waits (its answers to `answers`); without realtime, finishes it at once.
  void run_work(std::vector<std::string>& answers) {
    while (fd >= 0 && !current && session.has_work()) {
      Executed e = session.start_next();
      if (options.realtime && e.seconds > 0) {
        deadline = net::after_seconds(e.seconds);
        current = std::move(e);
      } else {
        session.finish(std::move(e), answers);
      }
    }
  }
  void run_work() {
    std::vector<std::string> answers;
    run_work(answers);
    queue_lines(answers);
  }

  void run() {
    bool stop = false;
    while (!stop) {
      if (fd >= 0 && !closing) run_work();
      if (fd >= 0 && current && (session.aborted() || net::Clock::now() >= deadline)) {
        std::vector<std::string> answers;
        session.finish(std::move(*current), answers);
        current.reset();
        queue_lines(answers);
        continue;
      }
      if (fd >= 0 && closing && out.empty()) {
        drop("protocol error");
        continue;
      }
      if (fd >= 0 && out.size() > options.max_output_bytes) {
        drop("it does not read its answers");
        continue;
      }
      pollfd p[3] = {{wake[0], POLLIN, 0}, {listen_fd, POLLIN, 0}, {-1, 0, 0}};
      int timeout = -1;
      if (fd >= 0) {
        p[2].fd = fd;
        p[2].events = static_cast<short>((closing ? 0 : POLLIN) | (out.empty() ? 0 : POLLOUT));
        if (current) timeout = net::ms_until(deadline);
        if (!out.empty()) {
          const int t = net::ms_until(last_sent + std::chrono::microseconds(static_cast<long long>(
                                                      options.send_timeout_s * 1e6)));
          if (t == 0) {
            drop("nothing could be sent to it for the send timeout");
            continue;
          }
          timeout = timeout < 0 ? t : std::min(timeout, t);
        }
      }
      const int r = ::poll(p, fd >= 0 ? 3 : 2, timeout);
      if (r < 0) {
        if (errno == EINTR) continue;
        throw Error("I++ server: poll: " + std::string(std::strerror(errno)));
      }
      if (p[0].revents & POLLIN) {
        char drain[64];
        while (::read(wake[0], drain, sizeof drain) > 0) {
        }
        stop = true;
      }
      if (p[1].revents & POLLIN) accept_client();
      if (fd >= 0 && p[2].fd == fd) {
        if (p[2].revents & (POLLERR | POLLNVAL)) {
          drop("connection error");
          continue;
        }
        if (p[2].revents & POLLOUT) write_client();
        if (fd >= 0 && (p[2].revents & (POLLIN | POLLHUP))) read_client();
      }
    }
    if (fd >= 0) drop("the server stops");
  }
};

Server::Server(Session& session, const ServerOptions& options)
    : impl_(std::make_unique<Impl>(session, options)) {
  impl_->listen();
}
Server::~Server() = default;
std::uint16_t Server::port() const noexcept { return impl_->port; }
void Server::run() { impl_->run(); }
void Server::request_stop() noexcept {
  const char c = 's';
  const ssize_t ignored = ::write(impl_->wake[1], &c, 1);
  (void)ignored;
}

}  // namespace cmmcomp::ipp
