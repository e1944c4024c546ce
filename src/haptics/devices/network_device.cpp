#include "haptics/devices/network_device.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <span>
#include <system_error>
#include <utility>

#include "core/error.hpp"

namespace tactus::haptics {
namespace {

std::string errno_text(int error) { return std::system_category().message(error); }

std::string endpoint(const NetworkConfig& config) {
  return config.address + ":" + std::to_string(config.port);
}

// Checked before anything is opened; a bad value is the user's to fix.
ReceiverConfig receiver_config(const NetworkConfig& config) {
  if (!(std::isfinite(config.timeout) && config.timeout > 0.0 && config.timeout <= 10.0))
    throw InputError("network device: timeout " + std::to_string(config.timeout) +
                     " s is out of range: must be in (0, 10]");
  if (config.port < 0 || config.port > 65535)
    throw InputError("network device: port " + std::to_string(config.port) +
                     " is out of range: must be in [0, 65535]");
  ReceiverConfig rc;
  rc.device_index = config.device_index;
  rc.timeout = static_cast<Nanos>(std::llround(config.timeout * 1e9));
  // Half the timeout: a pose delayed that much more than the newest is no longer worth
  // rendering, while the link as a whole is still alive.
  rc.stale_after = rc.timeout / 2;
  return rc;
}

Nanos to_nanos(double t) {
  if (!(t > 0.0)) return 0;  // also NaN
  return t >= 9.0e9 ? Nanos{9'000'000'000'000'000'000} : static_cast<Nanos>(std::llround(t * 1e9));
}

// Closes the descriptor unless released: the constructor may throw after opening it.
class FdGuard {
 public:
  explicit FdGuard(int fd) : fd_(fd) {}
  ~FdGuard() {
    if (fd_ >= 0) ::close(fd_);
  }
  FdGuard(const FdGuard&) = delete;
  FdGuard& operator=(const FdGuard&) = delete;
  int release() { return std::exchange(fd_, -1); }

 private:
  int fd_;
};

}  // namespace

NetworkDevice::NetworkDevice(NetworkConfig config, DeviceLimits limits)
    : config_(std::move(config)), limits_(limits), receiver_(receiver_config(config_)) {
  in_addr address{};
  if (::inet_pton(AF_INET, config_.address.c_str(), &address) != 1)
    throw InputError("network device: address '" + config_.address +
                     "' is not an IPv4 address (e.g. 127.0.0.1)");
  const bool loopback = (ntohl(address.s_addr) >> 24) == 127;
  if (!loopback && !config_.allow_remote)
    throw InputError("network device: refusing to bind " + endpoint(config_) +
                     ": not a loopback address (127.x.x.x), so any machine on the network "
                     "could drive the device; set allow_remote = true to permit it");

  const int opened = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (opened < 0) {
    const int error = errno;
    throw std::system_error(error, std::system_category(), "network device: socket()");
  }
  FdGuard guard(opened);
  const int on = 1;
  if (::setsockopt(opened, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on) != 0) {
    const int error = errno;
    throw std::system_error(error, std::system_category(), "network device: SO_REUSEADDR");
  }
  sockaddr_in local{};
  local.sin_family = AF_INET;
  local.sin_addr = address;
  local.sin_port = htons(static_cast<std::uint16_t>(config_.port));
  if (::bind(opened, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
    const int error = errno;
    throw InputError("network device: cannot bind UDP " + endpoint(config_) + ": " +
                     errno_text(error));
  }
  socklen_t length = sizeof local;
  if (::getsockname(opened, reinterpret_cast<sockaddr*>(&local), &length) != 0) {
    const int error = errno;
    throw std::system_error(error, std::system_category(), "network device: getsockname()");
  }
  bound_port_ = ntohs(local.sin_port);
  socket_ = guard.release();
}

NetworkDevice::~NetworkDevice() {
  if (socket_ >= 0) ::close(socket_);
}

DevicePose NetworkDevice::read(double t) {
  now_ = std::max(now_, to_nanos(t));
  int drained = 0;
  for (; drained < kMaxDatagramsPerRead; ++drained) {
    sockaddr_in from{};
    socklen_t from_length = sizeof from;
    // MSG_TRUNC returns the full datagram length, so an oversized one is not mistaken for
    // a packet of the buffer's size.
    const ssize_t n = ::recvfrom(socket_, buffer_.data(), buffer_.size(), MSG_DONTWAIT | MSG_TRUNC,
                                 reinterpret_cast<sockaddr*>(&from), &from_length);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK) ++counters_.receive_errors;
      break;
    }
    const std::size_t size = std::min(static_cast<std::size_t>(n), buffer_.size());
    if (receiver_.on_datagram(std::span<const std::byte>(buffer_).first(size), now_) &&
        from.sin_family == AF_INET) {
      has_peer_ = true;
      peer_address_ = from.sin_addr.s_addr;
      peer_port_ = from.sin_port;
    }
  }
  if (drained == kMaxDatagramsPerRead) ++counters_.reads_at_budget;
  return receiver_.pose();
}

void NetworkDevice::write(const Vec3& force, const Vec3& torque) {
  if (!has_peer_) return;
  ForcePacket packet;
  packet.device_index = config_.device_index;
  packet.sequence = force_sequence_++;
  packet.pose_sequence = receiver_.newest().sequence;
  packet.timestamp_ns = static_cast<std::uint64_t>(now_);
  packet.flags = safety_flags_ | (alive() ? 0u : std::uint32_t{kForceLinkTimeout});
  if (force.allFinite() && torque.allFinite()) {
    packet.force = force;
    packet.torque = torque;
  } else {
    packet.flags |= kForceNonFinite;  // the zero default is sent instead
  }
  const auto bytes = encode(packet);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_addr.s_addr = peer_address_;
  to.sin_port = peer_port_;
  const ssize_t n = ::sendto(socket_, bytes.data(), bytes.size(), MSG_DONTWAIT,
                             reinterpret_cast<const sockaddr*>(&to), sizeof to);
  if (n == static_cast<ssize_t>(bytes.size()))
    ++counters_.sent;
  else
    ++counters_.send_errors;
}

bool NetworkDevice::alive() const { return receiver_.alive(now_); }

}  // namespace tactus::haptics
