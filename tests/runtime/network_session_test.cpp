// A real-time run driven over the UDP bridge by a driver thread, as an external device
// driver process would: poses in, forces out, and a force that fades when the driver stops.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <optional>
#include <string>
#include <thread>

#include "core/clock.hpp"
#include "haptics/devices/network_protocol.hpp"
#include "runtime/session.hpp"
#include "scene/scene.hpp"

namespace tactus::runtime {
namespace {

TEST(NetworkSession, AnExternalDriverFeelsTheTissueAndTheForceFadesWhenItStops) {
  // An unprivileged port unlikely to clash between concurrent test runs.
  const int port = 40000 + static_cast<int>(getpid() % 20000);
  std::string text(scene::default_scene_text());
  const auto devices = text.find("[devices.hand]"), tools = text.find("[tools.finger]");
  text = text.substr(0, devices) +
         "[devices.hand]\ntype = \"network\"\nport = " + std::to_string(port) +
         "\ntimeout = 0.05\nmax_force = 10.0\n\n" + text.substr(tools);
  const scene::Model model = scene::parse_scene(text, "network.toml");

  std::atomic<bool> stop_sending{false};
  std::atomic<int> forces_received{0};
  std::atomic<double> largest_force{0.0};
  std::thread driver([&] {
    const int fd = socket(AF_INET, SOCK_DGRAM, 0);
    ASSERT_GE(fd, 0);
    timeval tv{0, 200};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<std::uint16_t>(port));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    haptics::PosePacket pose;
    // The trajectory's clock starts at the first force back, not at the thread's start: on a
    // loaded machine the session may take longer to build and bind than the whole trajectory.
    std::optional<Nanos> t0;
    const Nanos waiting_since = now_ns();
    // Hover 2 mm above the block's top until the session answers; then descend to 6 mm into
    // it over 0.4 s, hold, and stop 0.8 s after the first answer.
    while (!stop_sending.load()) {
      if (!t0 && now_ns() - waiting_since > 30'000'000'000) break;  // the session never answered
      const double t = t0 ? static_cast<double>(now_ns() - *t0) * 1e-9 : 0.0;
      if (t > 0.8) break;
      pose.sequence++;
      pose.timestamp_ns = static_cast<std::uint64_t>(now_ns());
      pose.position = Vec3(0, 0, 0.028 - 0.008 * std::min(1.0, t / 0.4));
      const auto bytes = haptics::encode(pose);
      sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
      std::array<std::byte, 256> buffer;
      ssize_t n;
      while ((n = recv(fd, buffer.data(), buffer.size(), MSG_DONTWAIT)) > 0) {
        const auto force = haptics::decode_force(std::span(buffer.data(), static_cast<std::size_t>(n)));
        if (!force.ok()) continue;
        if (!t0) t0 = now_ns();
        forces_received.fetch_add(1);
        if (force.packet().force.norm() > largest_force.load()) largest_force.store(force.packet().force.norm());
      }
      sleep_until(now_ns() + 1'000'000);
    }
    close(fd);
  });

  SessionOptions o;
  o.scheduling = Scheduling::real_time;
  o.duration = 1.2;
  o.keep_frames = true;
  const SessionReport r = run_session(model, o);
  stop_sending = true;
  driver.join();

  EXPECT_GT(forces_received.load(), 300);
  // 4 mm into 30 kPa tissue through an 800 N/m coupling: about a newton.
  EXPECT_GT(largest_force.load(), 0.3);
  EXPECT_GT(r.devices[0].contact_frames, 100u);
  // Once the driver is silent the device is not alive: the force faded to zero.
  EXPECT_GE(r.devices[0].safety.device_stalls, 1u);
  ASSERT_FALSE(r.frames.empty());
  EXPECT_EQ(r.frames.back().force, Vec3::Zero());
  for (const HapticFrame& f : r.frames) ASSERT_LE(f.force.norm(), 10.0);
}

}  // namespace
}  // namespace tactus::runtime
