// SPDX-License-Identifier: MIT
/// @file The blocking I++ DME client (client.hpp).
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cmmcomp/ipp/client.hpp>
#include <cmmcomp/ipp/line.hpp>
#include <cmmcomp/ipp/socket.hpp>

namespace cmmcomp::ipp {

Client::Client(const std::string& host, std::uint16_t port, double timeout_s) {
  const sockaddr_in a = net::resolve(host, port);
  const std::string where = host + ":" + std::to_string(port);
  fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd_ < 0) throw Error("I++ client: socket: " + std::string(std::strerror(errno)));
  if (::connect(fd_, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
    if (errno != EINPROGRESS) {
      const std::string why = std::strerror(errno);
      ::close(fd_);
      throw Error("I++ client: cannot connect to " + where + ": " + why);
    }
    pollfd p{fd_, POLLOUT, 0};
    int err = 0;
    socklen_t len = sizeof err;
    if (::poll(&p, 1, net::ms_until(net::after_seconds(timeout_s))) != 1 ||
        ::getsockopt(fd_, SOL_SOCKET, SO_ERROR, &err, &len) != 0 || err != 0) {
      ::close(fd_);
      throw Error("I++ client: cannot connect to " + where + ": " +
                  (err != 0 ? std::strerror(err) : "timed out"));
    }
  }
}

Client::~Client() {
  if (fd_ >= 0) ::close(fd_);
}

void Client::send_raw(std::string_view bytes) {
  std::size_t sent = 0;
  const auto deadline = net::after_seconds(10.0);
  while (sent < bytes.size()) {
    const ssize_t n =
        ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) {
      sent += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
      throw Error("I++ client: send: " + std::string(std::strerror(errno)));
    }
    pollfd p{fd_, POLLOUT, 0};
    if (::poll(&p, 1, net::ms_until(deadline)) == 0) throw Error("I++ client: send timed out");
  }
}

std::string Client::send(std::string_view command) {
  std::string_view name = command.substr(0, command.find('('));
  while (!name.empty() && name.back() == ' ') name.remove_suffix(1);
  const bool fast = !name.empty() && name.back() == 'E';
  Tag tag;
  if (fast) {
    tag = make_tag(Tag::Queue::kFast, next_event_tag_);
    next_event_tag_ = next_event_tag_ % 9999 + 1;
  } else {
    tag = make_tag(Tag::Queue::kNormal, next_tag_);
    next_tag_ = next_tag_ % 99999 + 1;
  }
  std::string line(tag.view());
  line += ' ';
  line += command;
  line += "\r\n";
  send_raw(line);
  return std::string(tag.view());
}

bool Client::read_more(double timeout_s) {
  for (;;) {
    const std::size_t lf = rx_.find('\n');
    if (lf != std::string::npos) {
      std::string line = rx_.substr(0, lf);
      rx_.erase(0, lf + 1);
      if (!line.empty() && line.back() == '\r') line.pop_back();
      AnswerLine a;
      const ParseStatus st = parse_answer(line, a);
      if (st != ParseStatus::kBadTag && st != ParseStatus::kTooLong &&
          st != ParseStatus::kIllegalCharacter && !a.tag.is_reserved()) {
        pending_[std::string(a.tag.view())].push_back(std::move(line));
      } else {
        events_.push_back(std::move(line));
      }
      return true;
    }
    if (closed_) throw Error("I++ client: the server closed the connection");
    pollfd p{fd_, POLLIN, 0};
    const int r = ::poll(&p, 1, net::ms_until(net::after_seconds(timeout_s)));
    if (r == 0) return false;
    if (r < 0 && errno == EINTR) continue;
    char buffer[4096];
    const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
    if (n > 0) {
      rx_.append(buffer, static_cast<std::size_t>(n));
    } else if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
      closed_ = true;
    }
  }
}

Transaction Client::wait(const std::string& tag, double timeout_s) {
  Transaction t;
  t.tag = tag;
  const auto deadline = net::after_seconds(timeout_s);
  std::size_t used = 0;
  for (;;) {
    std::vector<std::string>& lines = pending_[tag];
    while (used < lines.size()) {
      const std::string& line = lines[used++];
      t.lines.push_back(line);
      AnswerLine a;
      if (parse_answer(line, a) != ParseStatus::kOk) continue;
      if (a.kind == AnswerLine::Kind::kAck) t.acknowledged = true;
      if (a.kind == AnswerLine::Kind::kData) t.data.emplace_back(a.data);
      if (a.kind == AnswerLine::Kind::kError) {
        ErrorAnswer e;
        ErrorReply r;
        if (parse_error(a.data, e) == ParseStatus::kOk) {
          r = {e.severity, e.number, std::string(e.cause), std::string(e.text)};
        } else {
          r.text = std::string(a.data);
        }
        t.errors.push_back(std::move(r));
      }
      const bool ends = a.kind == AnswerLine::Kind::kDone ||
                        (a.kind == AnswerLine::Kind::kError && !t.acknowledged);
      if (ends) {
        t.done = a.kind == AnswerLine::Kind::kDone;
        lines.erase(lines.begin(), lines.begin() + static_cast<std::ptrdiff_t>(used));
        return t;
      }
    }
    const int left = net::ms_until(deadline);
    if (left == 0 || !read_more(left / 1000.0)) {
      pending_[tag].erase(pending_[tag].begin(),
                          pending_[tag].begin() + static_cast<std::ptrdiff_t>(used));
      throw Error("I++ client: no end of transaction " + tag + " within the timeout");
    }
  }
}

Transaction Client::call(std::string_view command, double timeout_s) {
  return wait(send(command), timeout_s);
}

std::string Client::wait_event(double timeout_s) {
  const auto deadline = net::after_seconds(timeout_s);
  while (events_.empty()) {
    const int left = net::ms_until(deadline);
    if (left == 0 || !read_more(left / 1000.0)) {
      throw Error("I++ client: no event within the timeout");
    }
  }
  std::string e = events_.front();
  events_.erase(events_.begin());
  return e;
}

bool Client::wait_closed(double timeout_s) {
  const auto deadline = net::after_seconds(timeout_s);
  try {
    for (;;) {
      const int left = net::ms_until(deadline);
      if (left == 0 || !read_more(left / 1000.0)) return false;
    }
  } catch (const Error&) {
    return true;
  }
}

}  // namespace cmmcomp::ipp
