// libFuzzer target for the recording reader: any bytes either read (possibly cut short,
// with a reason) or raise InputError; whatever is read also goes through the CSV writers.
// Random mutations almost never keep a CRC-32 valid, so each input is read a second time
// with every chunk's checksum recomputed: that way the record decoders see damaged
// payloads too, not only the chunk framing.
#include <cstddef>
#include <cstdint>
#include <span>
#include <sstream>
#include <vector>

#include "core/error.hpp"
#include "runtime/recording_csv.hpp"
#include "runtime/recording_format.hpp"
#include "runtime/recording_reader.hpp"

namespace {

namespace layout = tactus::runtime::recording_format;

void read_and_export(std::span<const std::byte> bytes) {
  try {
    const tactus::runtime::Recording rec = tactus::runtime::read_recording(bytes, "fuzz.tacrec");
    std::ostringstream out;
    tactus::runtime::write_frames_csv(rec, out);
    tactus::runtime::write_steps_csv(rec, out);
    tactus::runtime::write_events_csv(rec, out);
  } catch (const tactus::InputError&) {
    // A clear error is the expected outcome for a bad file header.
  }
}

/// Rewrites the checksum of every whole chunk after the file header; true if any changed.
bool repair_checksums(std::vector<std::byte>& b) {
  bool changed = false;
  std::size_t pos = layout::file_prefix_size;
  while (b.size() - pos >= layout::chunk_head_size) {
    const std::uint32_t length = layout::get_u32(b.data() + pos + 12);
    if (b.size() - pos - layout::chunk_head_size < std::uint64_t{length} + layout::chunk_tail_size) break;
    const std::size_t magic = layout::chunk_magic.size();
    const std::uint32_t crc = layout::chunk_crc({b.data() + pos + magic, layout::chunk_head_size - magic},
                                                {b.data() + pos + layout::chunk_head_size, length});
    std::byte* at = b.data() + pos + layout::chunk_head_size + length;
    for (int i = 0; i < 4; ++i) {
      const auto v = static_cast<std::byte>((crc >> (8 * i)) & 0xffU);
      changed = changed || at[i] != v;
      at[i] = v;
    }
    pos += layout::chunk_head_size + length + layout::chunk_tail_size;
  }
  return changed;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  read_and_export(bytes);
  if (size < layout::file_prefix_size) return 0;
  std::vector<std::byte> repaired(bytes.begin(), bytes.end());
  if (repair_checksums(repaired)) read_and_export(repaired);
  return 0;
}
