#include "runtime/recording_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "runtime/recording_format.hpp"

namespace tactus::runtime {

namespace layout = recording_format;

namespace {

/// A chunk payload that does not decode: where (file offset) and why.
struct Malformed {
  std::size_t offset;
  std::string reason;
};

/// Little-endian reads inside one chunk payload; running past its end is Malformed.
class PayloadCursor {
 public:
  PayloadCursor(std::span<const std::byte> payload, std::size_t file_offset)
      : payload_(payload), file_offset_(file_offset) {}

  [[nodiscard]] std::size_t remaining() const { return payload_.size() - pos_; }
  [[nodiscard]] std::size_t offset() const { return file_offset_ + pos_; }

  const std::byte* take(std::size_t n, const std::string& what) {
    if (remaining() < n)
      throw Malformed{offset(), what + " needs " + std::to_string(n) + " bytes, the chunk has " +
                                    std::to_string(remaining()) + " left"};
    const std::byte* p = payload_.data() + pos_;
    pos_ += n;
    return p;
  }
  std::uint8_t u8(const std::string& what) { return std::to_integer<std::uint8_t>(*take(1, what)); }
  std::uint16_t u16(const std::string& what) { return layout::get_u16(take(2, what)); }
  std::uint32_t u32(const std::string& what) { return layout::get_u32(take(4, what)); }
  std::uint64_t u64(const std::string& what) { return layout::get_u64(take(8, what)); }
  double f64(const std::string& what) { return layout::get_f64(take(8, what)); }
  Vec3 vec3(const std::string& what) {
    const std::byte* p = take(24, what);
    return {layout::get_f64(p), layout::get_f64(p + 8), layout::get_f64(p + 16)};
  }
  std::string string(const std::string& what) {
    const std::size_t at = offset();
    const std::uint32_t n = u32(what + " length");
    if (n > remaining())
      throw Malformed{at, what + " length " + std::to_string(n) + " exceeds the " + std::to_string(remaining()) +
                              " bytes left in the chunk"};
    const std::byte* p = take(n, what);
    return {reinterpret_cast<const char*>(p), n};
  }
  void expect_end(const std::string& what) const {
    if (remaining() != 0) throw Malformed{offset(), std::to_string(remaining()) + " unexpected bytes after " + what};
  }

 private:
  std::span<const std::byte> payload_;
  std::size_t file_offset_;
  std::size_t pos_ = 0;
};

struct Chunk {
  std::size_t offset = 0;  ///< of its magic
  std::uint32_t kind = 0;
  std::uint32_t count = 0;
  std::span<const std::byte> payload;
  [[nodiscard]] std::size_t payload_offset() const { return offset + layout::chunk_head_size; }
  [[nodiscard]] std::size_t size() const { return layout::chunk_head_size + payload.size() + layout::chunk_tail_size; }
};

/// Frames the chunk starting at `pos`: empty on success, else why it cannot be used.
std::string frame_chunk(std::span<const std::byte> bytes, std::size_t pos, Chunk& out) {
  const std::size_t left = bytes.size() - pos;
  if (left < layout::chunk_head_size)
    return "cut short: the chunk header needs " + std::to_string(layout::chunk_head_size) + " bytes, the file has " +
           std::to_string(left);
  const std::byte* p = bytes.data() + pos;
  if (std::memcmp(p, layout::chunk_magic.data(), layout::chunk_magic.size()) != 0) return "bad chunk magic";
  out.offset = pos;
  out.kind = layout::get_u32(p + 4);
  out.count = layout::get_u32(p + 8);
  const std::uint32_t length = layout::get_u32(p + 12);
  if (left - layout::chunk_head_size < std::uint64_t{length} + layout::chunk_tail_size)
    return "cut short: " + std::to_string(length) + " payload bytes and a checksum declared, the file has " +
           std::to_string(left - layout::chunk_head_size);
  out.payload = bytes.subspan(pos + layout::chunk_head_size, length);
  const std::uint32_t stored = layout::get_u32(p + layout::chunk_head_size + length);
  const std::size_t magic = layout::chunk_magic.size();
  const std::uint32_t computed = layout::chunk_crc({p + magic, layout::chunk_head_size - magic}, out.payload);
  if (stored != computed) return "checksum mismatch";
  return {};
}

RecordingHeader decode_header(const Chunk& c) {
  if (c.kind != static_cast<std::uint32_t>(layout::ChunkKind::header))
    throw Malformed{c.offset + 4, "expected the header chunk, found a chunk of kind " + std::to_string(c.kind)};
  if (c.count != 1)
    throw Malformed{c.offset + 8, "header chunk declares " + std::to_string(c.count) + " records, expected 1"};
  PayloadCursor in(c.payload, c.payload_offset());
  RecordingHeader h;
  h.scene_name = in.string("scene name");
  h.scene_source = in.string("scene source");
  h.scene_text = in.string("scene text");
  h.mode = in.string("mode");
  h.haptic_rate = in.f64("haptic rate");
  h.simulation_rate = in.f64("simulation rate");
  const std::size_t at = in.offset();
  const std::uint32_t devices = in.u32("device count");
  // Every name takes at least its 4-byte length: bounds the count before reserving.
  if (devices > in.remaining() / 4)
    throw Malformed{at, "device count " + std::to_string(devices) + " does not fit in the " +
                            std::to_string(in.remaining()) + " bytes left in the chunk"};
  h.devices.reserve(devices);
  for (std::uint32_t i = 0; i < devices; ++i) h.devices.push_back(in.string("device " + std::to_string(i) + " name"));
  h.start_unix_ns = static_cast<std::int64_t>(in.u64("start time"));
  h.tactus_version = in.string("Tactus version");
  in.expect_end("the header fields");
  return h;
}

void check_fixed_size(const Chunk& c, std::size_t record_size, const char* what) {
  if (std::uint64_t{c.count} * record_size != c.payload.size())
    throw Malformed{c.offset + 8, std::string(what) + " chunk declares " + std::to_string(c.count) + " records (" +
                                      std::to_string(std::uint64_t{c.count} * record_size) +
                                      " bytes) but its payload has " + std::to_string(c.payload.size()) + " bytes"};
}

void decode_frames(const Chunk& c, std::size_t device_count, std::vector<HapticFrame>& out) {
  check_fixed_size(c, layout::frame_record_size, "frames");
  for (std::uint32_t i = 0; i < c.count; ++i) {
    const std::size_t at = c.payload_offset() + i * layout::frame_record_size;
    const std::byte* p = c.payload.data() + i * layout::frame_record_size;
    HapticFrame f;
    f.frame = layout::get_u64(p);
    f.t = layout::get_f64(p + 8);
    f.device = layout::get_u16(p + 16);
    f.contact = std::to_integer<std::uint8_t>(p[18]);
    f.flags = std::to_integer<std::uint8_t>(p[19]);
    f.buttons = layout::get_u32(p + 20);
    const auto vec3 = [&](std::size_t o) {
      return Vec3(layout::get_f64(p + o), layout::get_f64(p + o + 8), layout::get_f64(p + o + 16));
    };
    f.position = vec3(24);
    f.orientation =
        Quat(layout::get_f64(p + 48), layout::get_f64(p + 56), layout::get_f64(p + 64), layout::get_f64(p + 72));
    f.force = vec3(80);
    f.torque = vec3(104);
    f.proxy = vec3(128);
    f.compute_ns = layout::get_u32(p + 152);
    f.late_ns = static_cast<std::int32_t>(layout::get_u32(p + 156));
    // Checked here so that every consumer may index the header's device list.
    if (f.device >= device_count)
      throw Malformed{at + 16, "frame " + std::to_string(i) + " is for device " + std::to_string(f.device) +
                                   " but the header lists " + std::to_string(device_count) + " devices"};
    out.push_back(f);
  }
}

void decode_steps(const Chunk& c, std::vector<SimulationStep>& out) {
  check_fixed_size(c, layout::step_record_size, "steps");
  for (std::uint32_t i = 0; i < c.count; ++i) {
    const std::byte* p = c.payload.data() + i * layout::step_record_size;
    SimulationStep s;
    s.step = layout::get_u64(p);
    s.t = layout::get_f64(p + 8);
    s.compute_ns = layout::get_u32(p + 16);
    s.solver_iterations = layout::get_u32(p + 20);
    s.late_ns = static_cast<std::int32_t>(layout::get_u32(p + 24));
    out.push_back(s);
  }
}

void decode_events(const Chunk& c, std::vector<Event>& out) {
  if (c.count > c.payload.size() / layout::event_fixed_size)
    throw Malformed{c.offset + 8, "events chunk declares " + std::to_string(c.count) + " records, more than its " +
                                      std::to_string(c.payload.size()) + " payload bytes can hold"};
  PayloadCursor in(c.payload, c.payload_offset());
  for (std::uint32_t i = 0; i < c.count; ++i) {
    const std::string what = "event " + std::to_string(i);
    Event e;
    e.t = in.f64(what);
    const std::size_t kind_at = in.offset();
    const std::uint16_t kind = in.u16(what);
    if (kind >= event_kind_count) throw Malformed{kind_at, what + " has unknown kind " + std::to_string(kind)};
    e.kind = static_cast<EventKind>(kind);
    e.device = in.u16(what);
    e.value = in.f64(what);
    e.text = in.string(what + " text");
    out.push_back(std::move(e));
  }
  in.expect_end("the events");
}

void check_end(const Chunk& c, const Recording& r) {
  if (c.count != 0)
    throw Malformed{c.offset + 8, "end chunk declares " + std::to_string(c.count) + " records, expected 0"};
  if (c.payload.size() != layout::end_payload_size)
    throw Malformed{c.offset + 12, "end chunk payload has " + std::to_string(c.payload.size()) + " bytes, expected " +
                                       std::to_string(layout::end_payload_size)};
  const std::byte* p = c.payload.data();
  const std::uint64_t frames = layout::get_u64(p), steps = layout::get_u64(p + 8), events = layout::get_u64(p + 16);
  if (frames != r.frames.size() || steps != r.steps.size() || events != r.events.size())
    throw Malformed{c.payload_offset(), "end chunk counts " + std::to_string(frames) + " frames, " +
                                            std::to_string(steps) + " steps and " + std::to_string(events) +
                                            " events, the file holds " + std::to_string(r.frames.size()) + ", " +
                                            std::to_string(r.steps.size()) + " and " + std::to_string(r.events.size())};
}

[[noreturn]] void fail(const std::string& name, std::size_t offset, const std::string& reason) {
  throw InputError(SourceLocation{name, {}, {}, offset}, reason);
}

template <class T>
void truncate_to(std::vector<T>& v, std::size_t n) {
  v.erase(v.begin() + static_cast<std::ptrdiff_t>(n), v.end());
}

}  // namespace

Recording read_recording(std::span<const std::byte> bytes, std::string name) {
  const auto magic = std::as_bytes(std::span(layout::file_magic.data(), layout::file_magic.size()));
  const std::size_t compared = std::min(bytes.size(), magic.size());
  if (compared > 0 && std::memcmp(bytes.data(), magic.data(), compared) != 0)
    fail(name, 0, "not a Tactus recording (bad file magic)");
  if (bytes.size() < layout::file_prefix_size)
    fail(name, bytes.size(),
         "truncated file: " + std::to_string(bytes.size()) + " bytes, the file header needs " +
             std::to_string(layout::file_prefix_size));
  const std::uint32_t version = layout::get_u32(bytes.data() + layout::version_offset);
  if (version == 0 || version > layout::current_version)
    fail(name, layout::version_offset,
         "unsupported recording format version " + std::to_string(version) + " (this build reads versions 1 to " +
             std::to_string(layout::current_version) + ")");

  Recording rec;
  Chunk chunk;
  std::size_t pos = layout::file_prefix_size;
  if (std::string why = frame_chunk(bytes, pos, chunk); !why.empty()) fail(name, pos, "header chunk: " + why);
  try {
    rec.header = decode_header(chunk);
  } catch (const Malformed& m) {
    fail(name, m.offset, "header chunk: " + m.reason);
  }
  pos += chunk.size();
  rec.good_chunks = 1;

  for (std::uint64_t index = 1;; ++index) {
    const std::string where = "chunk " + std::to_string(index) + " at byte " + std::to_string(pos) + ": ";
    if (pos == bytes.size()) {
      rec.truncation = where + "the file ends without an end chunk (the writer did not close it)";
      break;
    }
    if (std::string why = frame_chunk(bytes, pos, chunk); !why.empty()) {
      rec.truncation = where + why;
      break;
    }
    const std::size_t frames = rec.frames.size(), steps = rec.steps.size(), events = rec.events.size();
    try {
      switch (static_cast<layout::ChunkKind>(chunk.kind)) {
        case layout::ChunkKind::frames:
          decode_frames(chunk, rec.header.devices.size(), rec.frames);
          break;
        case layout::ChunkKind::steps:
          decode_steps(chunk, rec.steps);
          break;
        case layout::ChunkKind::events:
          decode_events(chunk, rec.events);
          break;
        case layout::ChunkKind::end:
          check_end(chunk, rec);
          break;
        case layout::ChunkKind::header:
          throw Malformed{chunk.offset + 4, "a second header chunk"};
        default:
          throw Malformed{chunk.offset + 4, "unknown chunk kind " + std::to_string(chunk.kind)};
      }
    } catch (const Malformed& m) {
      truncate_to(rec.frames, frames);
      truncate_to(rec.steps, steps);
      truncate_to(rec.events, events);
      rec.truncation = where + "malformed at byte " + std::to_string(m.offset) + ": " + m.reason;
      break;
    }
    ++rec.good_chunks;
    pos += chunk.size();
    if (chunk.kind == static_cast<std::uint32_t>(layout::ChunkKind::end)) {
      // Bytes after the end chunk are not part of the recording.
      rec.complete = true;
      break;
    }
  }
  return rec;
}

Recording read_recording(const std::filesystem::path& path) {
  const std::string name = path.string();
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    throw InputError(SourceLocation{name, {}, {}, {}},
                     "cannot open recording: " + std::generic_category().message(err));
  }
  // Large reads until end of file: the file may still be growing while a run records it.
  constexpr std::size_t block = std::size_t{1} << 22;
  std::vector<std::byte> data;
  struct stat st {};
  if (::fstat(fd, &st) == 0 && st.st_size > 0) data.reserve(static_cast<std::size_t>(st.st_size) + block);
  for (;;) {
    const std::size_t used = data.size();
    data.resize(used + block);
    const ssize_t n = ::read(fd, data.data() + used, block);
    if (n < 0 && errno == EINTR) {
      data.resize(used);
      continue;
    }
    if (n < 0) {
      const int err = errno;
      ::close(fd);
      throw InputError(SourceLocation{name, {}, {}, used},
                       "cannot read recording: " + std::generic_category().message(err));
    }
    data.resize(used + static_cast<std::size_t>(n));
    if (n == 0) break;
  }
  ::close(fd);
  return read_recording(std::span<const std::byte>(data), name);
}

}  // namespace tactus::runtime
