// What the readers share: gzip, voxel decoding, checks, and the choice of reader.
#include "imaging/label_image.hpp"

#include <zlib.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/input_file.hpp"
#include "imaging/voxel_data.hpp"

namespace tactus::imaging {
namespace detail {

std::string gunzip(std::string_view data, const std::string& file, std::uint64_t offset) {
  z_stream zs{};
  // 16 + MAX_WBITS: a gzip header, not a raw zlib one.
  if (inflateInit2(&zs, 16 + MAX_WBITS) != Z_OK) throw std::runtime_error("zlib: inflateInit2 failed");
  std::string out;
  const std::size_t limit = max_input_bytes();
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  zs.avail_in = static_cast<uInt>(std::min<std::size_t>(data.size(), std::numeric_limits<uInt>::max()));
  std::size_t fed = zs.avail_in;
  int rc = Z_OK;
  while (rc != Z_STREAM_END) {
    if (zs.avail_in == 0 && fed < data.size()) {
      const std::size_t more = std::min<std::size_t>(data.size() - fed, std::numeric_limits<uInt>::max());
      zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data() + fed));
      zs.avail_in = static_cast<uInt>(more);
      fed += more;
    }
    const std::size_t before = out.size();
    out.resize(before + std::max<std::size_t>(1 << 20, before / 2));
    zs.next_out = reinterpret_cast<Bytef*>(out.data() + before);
    zs.avail_out = static_cast<uInt>(std::min<std::size_t>(out.size() - before, std::numeric_limits<uInt>::max()));
    const uInt avail_before = zs.avail_out;
    rc = inflate(&zs, Z_NO_FLUSH);
    out.resize(before + (avail_before - zs.avail_out));
    const std::uint64_t at = offset + (fed - zs.avail_in);
    if (rc == Z_STREAM_END) break;
    if (rc == Z_BUF_ERROR && zs.avail_in == 0 && fed == data.size()) {
      inflateEnd(&zs);
      throw InputError(SourceLocation{file, {}, {}, at}, "gzip data ends early (truncated file?)");
    }
    if (rc != Z_OK && rc != Z_BUF_ERROR) {
      const std::string why = zs.msg ? zs.msg : "corrupt data";
      inflateEnd(&zs);
      throw InputError(SourceLocation{file, {}, {}, at}, "gzip: " + why);
    }
    if (out.size() > limit) {
      inflateEnd(&zs);
      throw InputError(SourceLocation{file, {}, {}, at},
                       fmt::format("gzip data inflates to more than {} bytes (TACTUS_MAX_INPUT_BYTES)", limit));
    }
  }
  inflateEnd(&zs);
  return out;
}

std::string gzip(std::string_view data) {
  z_stream zs{};
  if (deflateInit2(&zs, Z_DEFAULT_COMPRESSION, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("zlib: deflateInit2 failed");
  std::string out(deflateBound(&zs, static_cast<uLong>(data.size())), '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  zs.avail_in = static_cast<uInt>(data.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = static_cast<uInt>(out.size());
  const int rc = deflate(&zs, Z_FINISH);
  out.resize(zs.total_out);
  deflateEnd(&zs);
  if (rc != Z_STREAM_END) throw std::runtime_error("zlib: deflate failed");
  return out;
}

std::size_t voxel_bytes(VoxelType type) {
  switch (type) {
    case VoxelType::u8:
    case VoxelType::i8: return 1;
    case VoxelType::i16:
    case VoxelType::u16: return 2;
    case VoxelType::i32:
    case VoxelType::u32:
    case VoxelType::f32: return 4;
    case VoxelType::f64: return 8;
  }
  return 1;
}

namespace {

template <typename T>
T load(const char* p, bool swap) {
  std::array<char, sizeof(T)> b;
  std::memcpy(b.data(), p, sizeof(T));
  if (swap) std::reverse(b.begin(), b.end());
  T v;
  std::memcpy(&v, b.data(), sizeof(T));
  return v;
}

double load_value(const char* p, VoxelType type, bool swap) {
  switch (type) {
    case VoxelType::u8: return static_cast<unsigned char>(*p);
    case VoxelType::i8: return static_cast<signed char>(*p);
    case VoxelType::i16: return load<std::int16_t>(p, swap);
    case VoxelType::u16: return load<std::uint16_t>(p, swap);
    case VoxelType::i32: return load<std::int32_t>(p, swap);
    case VoxelType::u32: return load<std::uint32_t>(p, swap);
    case VoxelType::f32: return load<float>(p, swap);
    case VoxelType::f64: return load<double>(p, swap);
  }
  return 0.0;
}

}  // namespace

std::vector<std::int32_t> decode_labels(std::string_view data, VoxelType type, bool big_endian, std::size_t count,
                                        const std::string& file, std::uint64_t data_offset, double slope,
                                        double intercept) {
  const std::size_t bytes = voxel_bytes(type);
  if (data.size() / bytes < count)
    throw InputError(SourceLocation{file, {}, {}, data_offset + data.size()},
                     fmt::format("voxel data ends early: {} bytes for {} voxels of {} byte{}", data.size(), count,
                                 bytes, bytes == 1 ? "" : "s"));
  const bool swap = big_endian != (std::endian::native == std::endian::big);
  const bool identity = slope == 1.0 && intercept == 0.0;
  std::vector<std::int32_t> labels(count);
  for (std::size_t v = 0; v < count; ++v) {
    const char* p = data.data() + v * bytes;
    if (type == VoxelType::u8 && identity) {
      labels[v] = static_cast<unsigned char>(*p);
      continue;
    }
    const double value = load_value(p, type, swap) * slope + intercept;
    if (!(std::abs(value) <= 2147483647.0) || value != std::round(value))
      throw InputError(SourceLocation{file, {}, {}, data_offset + v * bytes},
                       fmt::format("voxel {} holds {}, not an integer label", v, value));
    labels[v] = static_cast<std::int32_t>(value);
  }
  return labels;
}

void check_geometry(const LabelImage& image, const std::string& where_spacing) {
  const SourceLocation at{image.source, {}, {}, {}};
  for (int a = 0; a < 3; ++a) {
    if (image.size[a] == 0) throw InputError(at, fmt::format("the image has no voxels along axis {}", a + 1));
    if (!(std::isfinite(image.spacing[a]) && image.spacing[a] > 0.0))
      throw InputError(at, fmt::format("{}: spacing along axis {} is {}; it must be finite and positive",
                                       where_spacing, a + 1, image.spacing[a]));
  }
  if (!image.direction.allFinite() || !image.origin.allFinite())
    throw InputError(at, "the orientation or origin is not finite");
  if (std::abs(image.direction.determinant()) < 1e-6)
    throw InputError(at, "the image axes are not independent (their directions are coplanar)");
}

}  // namespace detail

std::vector<LabelVoxels> count_labels(const LabelImage& image) {
  std::map<std::int32_t, std::size_t> counts;
  for (std::int32_t l : image.labels)
    if (l != 0) ++counts[l];
  std::vector<LabelVoxels> out;
  out.reserve(counts.size());
  for (const auto& entry : counts) out.push_back({entry.first, entry.second});
  return out;
}

LabelImage read_label_image(const std::filesystem::path& path, const std::optional<Vec3>& png_spacing) {
  const std::string name = path.filename().string();
  auto ends_with = [&](std::string_view suffix) {
    return name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  const bool png_stack = std::filesystem::is_directory(path) || name.find_first_of("*?[") != std::string::npos ||
                         ends_with(".png");
  if (png_stack) {
    if (!png_spacing)
      throw InputError(SourceLocation{path.string(), {}, {}, {}},
                       "a PNG slice stack needs --spacing SX,SY,SZ (metres)");
    return read_png_stack(path, *png_spacing);
  }
  if (ends_with(".nii") || ends_with(".nii.gz")) return read_nifti(path);
  if (ends_with(".nrrd")) return read_nrrd(path);
  throw InputError(SourceLocation{path.string(), {}, {}, {}},
                   "unknown label image format (.nii, .nii.gz, .nrrd, a directory or glob of .png slices)");
}

}  // namespace tactus::imaging
