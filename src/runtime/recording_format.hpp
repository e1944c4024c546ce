#pragma once
// The byte layout shared by the recording writer and reader (docs/recording-format.md):
// magic numbers, chunk kinds, record sizes and explicit little-endian encoding, so the
// file is the same whatever the host's byte order or struct padding.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace tactus::runtime::recording_format {

inline constexpr std::string_view file_magic{"TACREC\0\0", 8};
inline constexpr std::uint32_t current_version = 1;
inline constexpr std::size_t version_offset = 8;
inline constexpr std::size_t file_prefix_size = 12;  ///< magic + version

inline constexpr std::string_view chunk_magic{"TRCK", 4};
enum class ChunkKind : std::uint32_t { header = 1, frames = 2, steps = 3, events = 4, end = 5 };
inline constexpr std::size_t chunk_head_size = 16;  ///< magic, kind, count, payload length
inline constexpr std::size_t chunk_tail_size = 4;   ///< CRC-32
/// A chunk larger than this is refused by the writer; keeps the CRC input within zlib's range.
inline constexpr std::size_t max_payload_bytes = std::size_t{1} << 30;

inline constexpr std::size_t frame_record_size = 160;
inline constexpr std::size_t step_record_size = 28;
inline constexpr std::size_t event_fixed_size = 24;  ///< t, kind, device, value, text length
inline constexpr std::size_t end_payload_size = 24;  ///< frame, step and event totals

inline void put_u8(std::string& out, std::uint8_t v) { out.push_back(static_cast<char>(v)); }
inline void put_u16(std::string& out, std::uint16_t v) {
  for (int i = 0; i < 2; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xffU));
}
inline void put_u32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xffU));
}
inline void put_u64(std::string& out, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xffU));
}
inline void put_i32(std::string& out, std::int32_t v) { put_u32(out, static_cast<std::uint32_t>(v)); }
inline void put_i64(std::string& out, std::int64_t v) { put_u64(out, static_cast<std::uint64_t>(v)); }
inline void put_f64(std::string& out, double v) { put_u64(out, std::bit_cast<std::uint64_t>(v)); }

inline std::uint16_t get_u16(const std::byte* p) {
  return static_cast<std::uint16_t>(std::to_integer<unsigned>(p[0]) | (std::to_integer<unsigned>(p[1]) << 8));
}
inline std::uint32_t get_u32(const std::byte* p) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | std::to_integer<std::uint32_t>(p[i]);
  return v;
}
inline std::uint64_t get_u64(const std::byte* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | std::to_integer<std::uint64_t>(p[i]);
  return v;
}
inline double get_f64(const std::byte* p) { return std::bit_cast<double>(get_u64(p)); }

/// zlib's CRC-32 of kind, count, length and payload: the chunk's bytes after its magic.
std::uint32_t chunk_crc(std::span<const std::byte> head_after_magic, std::span<const std::byte> payload);

}  // namespace tactus::runtime::recording_format
