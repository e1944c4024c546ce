#include "runtime/recording_format.hpp"

#include <zlib.h>

namespace tactus::runtime::recording_format {

std::uint32_t chunk_crc(std::span<const std::byte> head_after_magic, std::span<const std::byte> payload) {
  uLong crc = crc32_z(0L, Z_NULL, 0);
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(head_after_magic.data()), head_after_magic.size());
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(payload.data()), payload.size());
  return static_cast<std::uint32_t>(crc);
}

}  // namespace tactus::runtime::recording_format
