#pragma once
// A device driven over UDP by an external driver process (docs/network-protocol.md): the
// driver sends poses, Tactus answers each haptic frame with a force. read() polls a
// non-blocking socket, so a silent or flooding peer can neither block nor stall the loop.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

#include "haptics/device.hpp"
#include "haptics/devices/network_protocol.hpp"

namespace tactus::haptics {

struct NetworkConfig {
  std::string address = "127.0.0.1";  ///< IPv4 address to bind
  int port = 47600;                   ///< 0 binds an ephemeral port (see bound_port())
  double timeout = 0.05;              ///< [s] not alive after this long without a valid pose
  bool allow_remote = false;          ///< permit a non-loopback bind address
  std::uint16_t device_index = 0;     ///< poses for other indices are ignored
};

struct NetworkCounters {
  std::uint64_t sent = 0;
  std::uint64_t send_errors = 0;
  std::uint64_t receive_errors = 0;
  std::uint64_t reads_at_budget = 0;  ///< read() calls that left datagrams for the next frame
};

class NetworkDevice final : public Device {
 public:
  /// Datagrams drained per read(): bounds the time one read can take under a flood.
  static constexpr int kMaxDatagramsPerRead = 64;

  /// Binds the socket. InputError for a bad configuration, a non-loopback address without
  /// allow_remote, or a failed bind (the message names address, port and reason).
  NetworkDevice(NetworkConfig config, DeviceLimits limits);
  ~NetworkDevice() override;

  /// Drains pending datagrams and returns the newest valid pose (the default pose before
  /// the first). t also stamps arrivals and outgoing forces.
  DevicePose read(double t) override;
  /// Sends a force packet to where the newest valid pose came from; nothing before the
  /// first. Send errors are counted, never thrown.
  void write(const Vec3& force, const Vec3& torque) override;
  [[nodiscard]] bool alive() const override;
  [[nodiscard]] const DeviceLimits& limits() const override { return limits_; }
  [[nodiscard]] const char* kind() const override { return "network"; }

  /// Safety flags (SafetyOutput::flags, ForceFlag bits 0–4) sent with every force.
  void set_safety_flags(std::uint32_t flags) { safety_flags_ = flags; }
  [[nodiscard]] std::uint16_t bound_port() const { return bound_port_; }
  [[nodiscard]] const ReceiverCounters& receiver_counters() const { return receiver_.counters(); }
  [[nodiscard]] const NetworkCounters& counters() const { return counters_; }

 private:
  NetworkConfig config_;
  DeviceLimits limits_;
  PoseReceiver receiver_;
  NetworkCounters counters_;
  int socket_ = -1;
  std::uint16_t bound_port_ = 0;
  bool has_peer_ = false;
  std::uint32_t peer_address_ = 0;  ///< network byte order
  std::uint16_t peer_port_ = 0;     ///< network byte order
  Nanos now_ = 0;  ///< time of the last read()
  std::uint32_t force_sequence_ = 0;
  std::uint32_t safety_flags_ = 0;
  // Larger than any valid packet, so an oversized datagram is still seen as the wrong size.
  std::array<std::byte, 256> buffer_{};
};

}  // namespace tactus::haptics
