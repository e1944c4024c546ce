#pragma once
// Writes a recording file (docs/recording-format.md). Records are buffered per kind and
// written as one checksummed chunk with write(2) when a chunk fills up or on flush(), so
// everything flushed survives the process being killed; a crash loses at most the chunks
// still being filled. Not thread-safe: one recorder thread owns the writer.
#include <cstdint>
#include <filesystem>
#include <string>

#include "runtime/recording.hpp"

namespace tactus::runtime {

class RecordingWriter {
 public:
  static constexpr std::uint32_t frames_per_chunk = 256;
  static constexpr std::uint32_t steps_per_chunk = 256;
  static constexpr std::uint32_t events_per_chunk = 64;
  static constexpr std::size_t event_bytes_per_chunk = 64 * 1024;

  /// Creates (or truncates) the file and writes the file header and header chunk.
  /// InputError naming the file and the system's reason if it cannot be created or written.
  RecordingWriter(const std::filesystem::path& path, const RecordingHeader& header);
  /// Closes cleanly (end chunk) if close() was not called; never throws.
  ~RecordingWriter();

  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;
  RecordingWriter(RecordingWriter&& other) noexcept;
  RecordingWriter& operator=(RecordingWriter&& other) noexcept;

  /// Buffer one record; a full chunk is written at once. A frame's device must index the
  /// header's device list (std::invalid_argument otherwise). InputError if a write fails.
  void append(const HapticFrame& frame);
  void append(const SimulationStep& step);
  void append(const Event& event);

  /// Writes every partly filled chunk now (frames, then steps, then events).
  void flush();
  /// Flushes, writes the end chunk and closes the file. Later appends throw std::logic_error.
  void close();

  [[nodiscard]] bool is_open() const { return fd_ >= 0; }
  /// Bytes handed to the operating system so far (buffered records not included).
  [[nodiscard]] std::uint64_t bytes_written() const { return bytes_written_; }
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  struct Pending {
    std::string payload;
    std::uint32_t count = 0;
  };

  void write_chunk(std::uint32_t kind, Pending& pending);
  void write_all(const std::string& bytes);
  void require_open() const;
  void release() noexcept;

  std::filesystem::path path_;
  int fd_ = -1;
  bool failed_ = false;  ///< a write failed: the file ends in a partial chunk
  std::size_t device_count_ = 0;
  std::uint64_t bytes_written_ = 0;
  std::uint64_t total_frames_ = 0, total_steps_ = 0, total_events_ = 0;
  Pending frames_, steps_, events_;
  std::string chunk_;  ///< reused buffer: one chunk goes out in one write(2)
};

}  // namespace tactus::runtime
