#include "runtime/recording_writer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <limits>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "core/error.hpp"
#include "runtime/recording_format.hpp"

namespace tactus::runtime {

namespace layout = recording_format;

namespace {

void put_string(std::string& out, const std::string& s) {
  if (s.size() > layout::max_payload_bytes)
    throw std::length_error("recording: string of " + std::to_string(s.size()) + " bytes is too long");
  layout::put_u32(out, static_cast<std::uint32_t>(s.size()));
  out += s;
}

void put_vec3(std::string& out, const Vec3& v) {
  for (int k = 0; k < 3; ++k) layout::put_f64(out, v[k]);
}

std::string encode_header(const RecordingHeader& h) {
  std::string out;
  put_string(out, h.scene_name);
  put_string(out, h.scene_source);
  put_string(out, h.scene_text);
  put_string(out, h.mode);
  layout::put_f64(out, h.haptic_rate);
  layout::put_f64(out, h.simulation_rate);
  layout::put_u32(out, static_cast<std::uint32_t>(h.devices.size()));
  for (const auto& name : h.devices) put_string(out, name);
  layout::put_i64(out, h.start_unix_ns);
  put_string(out, h.tactus_version);
  return out;
}

std::string system_reason(int err) { return std::generic_category().message(err); }

}  // namespace

RecordingWriter::RecordingWriter(const std::filesystem::path& path, const RecordingHeader& header)
    : path_(path), device_count_(header.devices.size()) {
  // Device indices are 16 bits in every record.
  if (header.devices.size() > std::numeric_limits<std::uint16_t>::max() + std::size_t{1})
    throw std::invalid_argument("recording: more than 65536 devices");
  Pending head;
  head.payload = encode_header(header);
  head.count = 1;

  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    const int err = errno;
    throw InputError(SourceLocation{path.string(), {}, {}, {}}, "cannot create recording: " + system_reason(err));
  }
  try {
    std::string prefix(layout::file_magic);
    layout::put_u32(prefix, layout::current_version);
    write_all(prefix);
    write_chunk(static_cast<std::uint32_t>(layout::ChunkKind::header), head);
  } catch (...) {
    release();
    throw;
  }
}

RecordingWriter::~RecordingWriter() {
  try {
    close();
  } catch (...) {
    // A destructor must not throw; the file then ends without its end chunk, which the
    // reader reports as an incomplete recording.
  }
  release();
}

RecordingWriter::RecordingWriter(RecordingWriter&& other) noexcept
    : path_(std::move(other.path_)),
      fd_(std::exchange(other.fd_, -1)),
      failed_(other.failed_),
      device_count_(other.device_count_),
      bytes_written_(other.bytes_written_),
      total_frames_(other.total_frames_),
      total_steps_(other.total_steps_),
      total_events_(other.total_events_),
      frames_(std::move(other.frames_)),
      steps_(std::move(other.steps_)),
      events_(std::move(other.events_)) {}

RecordingWriter& RecordingWriter::operator=(RecordingWriter&& other) noexcept {
  if (this != &other) {
    try {
      close();
    } catch (...) {
      // As in the destructor: the old file stays readable up to its last chunk.
    }
    release();
    path_ = std::move(other.path_);
    fd_ = std::exchange(other.fd_, -1);
    failed_ = other.failed_;
    device_count_ = other.device_count_;
    bytes_written_ = other.bytes_written_;
    total_frames_ = other.total_frames_;
    total_steps_ = other.total_steps_;
    total_events_ = other.total_events_;
    frames_ = std::move(other.frames_);
    steps_ = std::move(other.steps_);
    events_ = std::move(other.events_);
  }
  return *this;
}

void RecordingWriter::append(const HapticFrame& f) {
  require_open();
  if (f.device >= device_count_)
    throw std::invalid_argument("recording: frame for device " + std::to_string(f.device) + " but the header lists " +
                                std::to_string(device_count_) + " devices");
  std::string& out = frames_.payload;
  layout::put_u64(out, f.frame);
  layout::put_f64(out, f.t);
  layout::put_u16(out, f.device);
  layout::put_u8(out, f.contact);
  layout::put_u8(out, f.flags);
  layout::put_u32(out, f.buttons);
  put_vec3(out, f.position);
  layout::put_f64(out, f.orientation.w());
  layout::put_f64(out, f.orientation.x());
  layout::put_f64(out, f.orientation.y());
  layout::put_f64(out, f.orientation.z());
  put_vec3(out, f.force);
  put_vec3(out, f.torque);
  put_vec3(out, f.proxy);
  layout::put_u32(out, f.compute_ns);
  layout::put_i32(out, f.late_ns);
  if (++frames_.count >= frames_per_chunk) write_chunk(static_cast<std::uint32_t>(layout::ChunkKind::frames), frames_);
}

void RecordingWriter::append(const SimulationStep& s) {
  require_open();
  std::string& out = steps_.payload;
  layout::put_u64(out, s.step);
  layout::put_f64(out, s.t);
  layout::put_u32(out, s.compute_ns);
  layout::put_u32(out, s.solver_iterations);
  layout::put_i32(out, s.late_ns);
  if (++steps_.count >= steps_per_chunk) write_chunk(static_cast<std::uint32_t>(layout::ChunkKind::steps), steps_);
}

void RecordingWriter::append(const Event& e) {
  require_open();
  if (e.text.size() > layout::max_payload_bytes - layout::event_fixed_size)
    throw std::length_error("recording: event text of " + std::to_string(e.text.size()) + " bytes is too long");
  // Keep every chunk under the payload limit, however long the texts.
  if (events_.payload.size() + layout::event_fixed_size + e.text.size() > layout::max_payload_bytes)
    write_chunk(static_cast<std::uint32_t>(layout::ChunkKind::events), events_);
  std::string& out = events_.payload;
  layout::put_f64(out, e.t);
  layout::put_u16(out, static_cast<std::uint16_t>(e.kind));
  layout::put_u16(out, e.device);
  layout::put_f64(out, e.value);
  put_string(out, e.text);
  if (++events_.count >= events_per_chunk || events_.payload.size() >= event_bytes_per_chunk)
    write_chunk(static_cast<std::uint32_t>(layout::ChunkKind::events), events_);
}

void RecordingWriter::flush() {
  require_open();
  if (frames_.count > 0) write_chunk(static_cast<std::uint32_t>(layout::ChunkKind::frames), frames_);
  if (steps_.count > 0) write_chunk(static_cast<std::uint32_t>(layout::ChunkKind::steps), steps_);
  if (events_.count > 0) write_chunk(static_cast<std::uint32_t>(layout::ChunkKind::events), events_);
}

void RecordingWriter::close() {
  if (fd_ < 0) return;
  if (!failed_) {
    flush();
    Pending end;
    layout::put_u64(end.payload, total_frames_);
    layout::put_u64(end.payload, total_steps_);
    layout::put_u64(end.payload, total_events_);
    write_chunk(static_cast<std::uint32_t>(layout::ChunkKind::end), end);
  }
  const int fd = std::exchange(fd_, -1);
  if (::close(fd) != 0 && errno != EINTR) {
    const int err = errno;
    throw InputError(SourceLocation{path_.string(), {}, {}, {}}, "cannot close recording: " + system_reason(err));
  }
}

void RecordingWriter::write_chunk(std::uint32_t kind, Pending& pending) {
  chunk_.clear();
  chunk_.reserve(layout::chunk_head_size + pending.payload.size() + layout::chunk_tail_size);
  chunk_ += layout::chunk_magic;
  layout::put_u32(chunk_, kind);
  layout::put_u32(chunk_, pending.count);
  layout::put_u32(chunk_, static_cast<std::uint32_t>(pending.payload.size()));
  chunk_ += pending.payload;
  const auto* bytes = reinterpret_cast<const std::byte*>(chunk_.data());
  const std::size_t magic = layout::chunk_magic.size();
  const std::uint32_t crc = layout::chunk_crc({bytes + magic, layout::chunk_head_size - magic},
                                              {bytes + layout::chunk_head_size, pending.payload.size()});
  layout::put_u32(chunk_, crc);
  write_all(chunk_);
  switch (static_cast<layout::ChunkKind>(kind)) {
    case layout::ChunkKind::frames:
      total_frames_ += pending.count;
      break;
    case layout::ChunkKind::steps:
      total_steps_ += pending.count;
      break;
    case layout::ChunkKind::events:
      total_events_ += pending.count;
      break;
    default:
      break;
  }
  pending.payload.clear();
  pending.count = 0;
}

void RecordingWriter::write_all(const std::string& bytes) {
  require_open();
  if (failed_)
    throw InputError(SourceLocation{path_.string(), {}, {}, {}}, "cannot write recording: an earlier write failed");
  const char* p = bytes.data();
  std::size_t left = bytes.size();
  while (left > 0) {
    const ssize_t n = ::write(fd_, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      failed_ = true;
      throw InputError(SourceLocation{path_.string(), {}, {}, {}}, "cannot write recording: " + system_reason(err));
    }
    p += n;
    left -= static_cast<std::size_t>(n);
    bytes_written_ += static_cast<std::uint64_t>(n);
  }
}

void RecordingWriter::require_open() const {
  if (fd_ < 0) throw std::logic_error("recording: writer for " + path_.string() + " is closed");
}

void RecordingWriter::release() noexcept {
  if (fd_ >= 0) ::close(std::exchange(fd_, -1));
}

}  // namespace tactus::runtime
