// SPDX-License-Identifier: MIT
/// @file CanServer: a raw SocketCAN socket (id filter, CAN FD) and its poll loop around
/// CanRequestHandler, with heartbeats; parsing and printing of the base id.
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/plugins/can_server.hpp>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

namespace cmmcomp::plugins {
namespace {

std::int64_t now_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// The MTU of `interface` (16 classic, 72 CAN FD), or −1.
int interface_mtu(int socket, const std::string& interface) {
  ifreq request{};
  std::strncpy(request.ifr_name, interface.c_str(), IFNAMSIZ - 1);
  return ::ioctl(socket, SIOCGIFMTU, &request) == 0 ? request.ifr_mtu : -1;
}

}  // namespace

std::string format_can_base_id(std::uint32_t id) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%03X", static_cast<unsigned>(id));
  return text;
}

std::uint32_t parse_can_base_id(const std::string& text) {
  std::size_t used = 0;
  unsigned long v = 0;
  try {
    v = std::stoul(text, &used, 0);
  } catch (const std::exception&) {
    used = 0;
  }
  // std::stoul would take a leading blank or sign ("-0", " 0x300"): a user's id starts with a
  // digit.
  const bool digit_first = !text.empty() && text[0] >= '0' && text[0] <= '9';
  if (!digit_first || used != text.size() || v > can::kMaxStandardId - (can::kMessageCount - 1)) {
    throw ConfigError("--can-base-id '" + text + "': expected an 11-bit id ≤ " +
                      format_can_base_id(can::kMaxStandardId - (can::kMessageCount - 1)) +
                      ", e.g. " + format_can_base_id(can::kDefaultBaseId));
  }
  return static_cast<std::uint32_t>(v);
}

bool is_valid_can_interface_name(const std::string& name, std::string* why) {
  const auto fail = [why](const std::string& message) {
    if (why != nullptr) *why = message;
    return false;
  };
  if (name.empty() || name.size() >= IFNAMSIZ) {
    return fail("CAN interface name '" + name + "' is empty or longer than " +
                std::to_string(IFNAMSIZ - 1) + " bytes");
  }
  if (name == "." || name == "..") return fail("CAN interface name '" + name + "' is reserved");
  for (const char ch : name) {
    const auto byte = static_cast<unsigned char>(ch);
    if (ch == '/' || byte <= ' ' || byte == 0x7F) {
      return fail("CAN interface name '" + name +
                  "' has a '/', a blank or a control character (Linux refuses it)");
    }
  }
  return true;
}

bool CanServerOptions::is_valid(std::string* why) const {
  const auto fail = [why](const char* message) {
    if (why != nullptr) *why = message;
    return false;
  };
  if (!is_valid_can_interface_name(interface, why)) return false;
  if (base_id + can::kHeartbeatOffset > can::kMaxStandardId) {
    return fail("base id + 3 must be an 11-bit identifier (base id <= 0x7FC)");
  }
  if (part_timeout.count() <= 0) return fail("part timeout must be > 0");
  if (heartbeat_period.count() < 0) return fail("heartbeat period must be >= 0 (0: off)");
  return true;
}

CanServer::CanServer(const compensation::MoveCompensator& compensator,
                     const CanServerOptions& options)
    : options_(options), handler_(compensator, options.base_id, options.part_timeout) {
  handler_.set_outcome_log(options.outcome_log);
  std::string why;
  if (!options_.is_valid(&why)) throw ConfigError("CAN server options: " + why);
  socket_ = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC | SOCK_NONBLOCK, CAN_RAW);
  if (socket_ < 0) {
    const int e = errno;
    if (e == EAFNOSUPPORT) {
      throw Error(
          "no CAN support in this kernel (EAFNOSUPPORT): load the can and can-raw modules, or run "
          "under scripts/uml-run.sh");
    }
    throw Error(std::string("cannot open a CAN_RAW socket: ") + std::strerror(e));
  }
  const auto fail = [this](const std::string& message) {
    ::close(socket_);
    socket_ = -1;
    throw Error(message);
  };
  const unsigned index = ::if_nametoindex(options_.interface.c_str());
  if (index == 0) fail("no such interface " + options_.interface);
  // Only the request identifier, standard frames, no remote frames: everything else stays in
  // the kernel and costs the server nothing.
  can_filter filter{};
  filter.can_id = options_.base_id + can::kRequestOffset;
  filter.can_mask = CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG;
  if (::setsockopt(socket_, SOL_CAN_RAW, CAN_RAW_FILTER, &filter, sizeof filter) != 0) {
    fail(std::string("cannot set the CAN filter: ") + std::strerror(errno));
  }
  if (options_.fd) {
    const int mtu = interface_mtu(socket_, options_.interface);
    if (mtu != static_cast<int>(CANFD_MTU)) {
      fail(options_.interface + " is not a CAN FD interface (MTU " + std::to_string(mtu) +
           ", CAN FD needs 72: ip link set " + options_.interface + " mtu 72)");
    }
    const int on = 1;
    if (::setsockopt(socket_, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on) != 0) {
      fail(std::string("this kernel does not support CAN FD frames: ") + std::strerror(errno));
    }
  }
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(index);
  if (::bind(socket_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    fail("cannot bind to " + options_.interface + ": " + std::strerror(errno));
  }
}

CanServer::~CanServer() {
  if (socket_ >= 0) ::close(socket_);
}

std::string CanServer::where() const {
  return "SocketCAN " + options_.interface + (options_.fd ? " (CAN FD)" : "") + ", base id " +
         format_can_base_id(options_.base_id);
}

void CanServer::send(const CanFrameBatch& batch, bool as_fd) noexcept {
  std::uint64_t errors = 0;
  for (std::size_t i = 0; i < batch.size; ++i) {
    const can::Frame& f = batch.frames[i];
    canfd_frame k{};  // a classic can_frame is its first CAN_MTU bytes
    k.can_id = f.id & CAN_SFF_MASK;
    k.len = f.dlc;
    k.flags = as_fd ? CANFD_BRS : 0;
    std::memcpy(k.data, f.data.data(), f.data.size());
    const std::size_t size = as_fd ? CANFD_MTU : CAN_MTU;
    if (::send(socket_, &k, size, MSG_DONTWAIT) != static_cast<ssize_t>(size)) ++errors;
  }
  if (errors != 0) handler_.count_send_errors(errors);
}

void CanServer::send_heartbeat() noexcept {
  const can::HeartbeatInfo h = handler_.next_heartbeat();
  CanFrameBatch batch;
  for (std::uint8_t page = 0; page < can::kHeartbeatPages; ++page) {
    batch.push(can::encode_heartbeat(h, page, options_.base_id));
    if (batch.size == CanFrameBatch::kCapacity) {
      send(batch, false);  // classic: every node on the bus can read it
      batch.size = 0;
    }
  }
  send(batch, false);
}

void CanServer::run(const std::atomic<bool>& stop) {
  constexpr std::int64_t kStopCheckNs = 100'000'000;  // how soon `stop` is noticed
  constexpr int kFramesPerWakeup = 64;                // bounds one wake-up's work
  const std::int64_t period_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(options_.heartbeat_period).count();
  std::int64_t next_heartbeat_ns = now_ns();
  while (!stop.load(std::memory_order_relaxed)) {
    std::int64_t now = now_ns();
    if (period_ns > 0 && now >= next_heartbeat_ns) {
      send_heartbeat();
      next_heartbeat_ns = std::max(next_heartbeat_ns + period_ns, now);
    }
    CanFrameBatch expired;
    handler_.on_time(now, expired);
    send(expired, last_request_fd_);

    std::int64_t wait_ns = kStopCheckNs;
    if (period_ns > 0) wait_ns = std::min(wait_ns, next_heartbeat_ns - now);
    if (handler_.assembling()) wait_ns = std::min(wait_ns, handler_.deadline_ns() - now);
    wait_ns = std::max<std::int64_t>(wait_ns, 0);
    const timespec timeout{static_cast<time_t>(wait_ns / 1'000'000'000),
                           static_cast<long>(wait_ns % 1'000'000'000)};
    pollfd p{socket_, POLLIN, 0};
    const int ready = ::ppoll(&p, 1, &timeout, nullptr);
    if (ready < 0) {
      if (errno == EINTR) continue;
      throw Error(std::string("poll on the CAN socket failed: ") + std::strerror(errno));
    }
    if (ready == 0) continue;
    if ((p.revents & (POLLERR | POLLHUP | POLLNVAL)) != 0 && (p.revents & POLLIN) == 0) {
      throw Error("the CAN socket on " + options_.interface + " failed (interface gone?)");
    }
    for (int i = 0; i < kFramesPerWakeup; ++i) {
      canfd_frame k{};  // large enough for either format; n tells which one came
      const ssize_t n = ::recv(socket_, &k, sizeof k, MSG_DONTWAIT);
      if (n < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) break;
        throw Error("reading from " + options_.interface + " failed: " + std::strerror(errno));
      }
      const bool is_fd = n == static_cast<ssize_t>(CANFD_MTU);
      if (!is_fd && n != static_cast<ssize_t>(CAN_MTU)) continue;
      can::Frame f;
      f.id = (k.can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_ERR_FLAG)) != 0
                 ? ~std::uint32_t{0}  // never a request id: counted as ignored
                 : (k.can_id & CAN_SFF_MASK);
      f.dlc = k.len;  // an FD frame longer than 8 bytes is a wrong-DLC reject
      std::memcpy(f.data.data(), k.data, std::min<std::size_t>(k.len, f.data.size()));
      last_request_fd_ = is_fd;
      CanFrameBatch out;
      handler_.on_frame(f, now_ns(), out);
      send(out, is_fd);
    }
  }
}

}  // namespace cmmcomp::plugins
