// NIfTI-1 single-file images (.nii, .nii.gz): the 348-byte header, then the voxels at
// vox_offset. Own reader rather than libnifti: it needs 150 lines, and every refusal can
// name the header field and its byte offset.
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/input_file.hpp"
#include "imaging/label_image.hpp"
#include "imaging/voxel_data.hpp"

namespace tactus::imaging {
namespace {

constexpr std::size_t kHeaderBytes = 348;
// Byte offsets of the header fields used.
constexpr std::size_t kDim = 40, kDatatype = 70, kPixdim = 76, kVoxOffset = 108, kSclSlope = 112,
                      kSclInter = 116, kXyztUnits = 123, kQformCode = 252, kSformCode = 254, kQuatern = 256,
                      kQoffset = 268, kSrow = 280, kMagic = 344;

class Header {
 public:
  Header(std::string_view bytes, std::string file) : b_(bytes), file_(std::move(file)) {
    std::int32_t size = 0;
    std::memcpy(&size, b_.data(), 4);
    if (size == 348) {
      swap_ = false;
    } else if (static_cast<std::int32_t>(__builtin_bswap32(static_cast<std::uint32_t>(size))) == 348) {
      swap_ = true;
    } else {
      fail(0, fmt::format("sizeof_hdr is {}, not 348: not a NIfTI-1 file", size));
    }
  }
  template <typename T>
  T get(std::size_t offset) const {
    std::array<char, sizeof(T)> raw;
    std::memcpy(raw.data(), b_.data() + offset, sizeof(T));
    if (swap_) std::reverse(raw.begin(), raw.end());
    T v;
    std::memcpy(&v, raw.data(), sizeof(T));
    return v;
  }
  [[noreturn]] void fail(std::uint64_t offset, const std::string& reason) const {
    throw InputError(SourceLocation{file_, {}, {}, offset}, reason);
  }
  [[nodiscard]] bool big_endian() const { return swap_ != (std::endian::native == std::endian::big); }

 private:
  std::string_view b_;
  std::string file_;
  bool swap_ = false;
};

detail::VoxelType voxel_type(const Header& h) {
  const auto code = h.get<std::int16_t>(kDatatype);
  switch (code) {
    case 2: return detail::VoxelType::u8;
    case 256: return detail::VoxelType::i8;
    case 4: return detail::VoxelType::i16;
    case 512: return detail::VoxelType::u16;
    case 8: return detail::VoxelType::i32;
    case 768: return detail::VoxelType::u32;
    case 16: return detail::VoxelType::f32;
    case 64: return detail::VoxelType::f64;
    default:
      h.fail(kDatatype, fmt::format("datatype {} is not supported for labels (uint8, int8, int16, uint16, int32, "
                                    "uint32, float32, float64)",
                                    code));
  }
}

/// Metres per file unit, from xyzt_units (NIfTI: 1 metre, 2 mm, 3 µm; 0, unknown, is
/// taken as mm, what scanners and segmentation tools write).
double metres_per_unit(const Header& h) {
  const int code = h.get<std::uint8_t>(kXyztUnits) & 7;
  switch (code) {
    case 0:
    case 2: return 1e-3;
    case 1: return 1.0;
    case 3: return 1e-6;
    default: h.fail(kXyztUnits, fmt::format("xyzt_units gives spatial unit code {}, not a length", code));
  }
}

}  // namespace

LabelImage read_nifti(const std::filesystem::path& path) {
  const std::string name = path.filename().string();
  const bool gz = name.size() > 3 && name.compare(name.size() - 3, 3, ".gz") == 0;
  return detail::parse_nifti(read_input_file(path), path.string(), gz);
}

LabelImage detail::parse_nifti(std::string data, const std::string& file, bool gz) {
  if (gz) data = detail::gunzip(data, file, 0);
  if (data.size() < kHeaderBytes)
    throw InputError(SourceLocation{file, {}, {}, data.size()},
                     fmt::format("{} bytes, shorter than the 348-byte NIfTI-1 header", data.size()));
  const Header h(data, file);
  if (std::memcmp(data.data() + kMagic, "n+1\0", 4) != 0) {
    if (std::memcmp(data.data() + kMagic, "ni1\0", 4) == 0)
      h.fail(kMagic, "magic 'ni1': a .hdr/.img pair; only single-file NIfTI (.nii) is read");
    h.fail(kMagic, "magic is not 'n+1': not a NIfTI-1 file");
  }

  LabelImage image;
  image.source = file;
  const auto ndim = h.get<std::int16_t>(kDim);
  if (ndim < 3 || ndim > 7) h.fail(kDim, fmt::format("dim[0] is {}; a label image has 3 dimensions", ndim));
  for (int a = 0; a < 3; ++a) {
    const auto n = h.get<std::int16_t>(kDim + 2 * (a + 1));
    if (n <= 0) h.fail(kDim + 2 * (a + 1), fmt::format("dim[{}] is {}; it must be positive", a + 1, n));
    image.size[a] = static_cast<std::size_t>(n);
  }
  for (int a = 3; a < ndim; ++a)
    if (h.get<std::int16_t>(kDim + 2 * (a + 1)) > 1)
      h.fail(kDim + 2 * (a + 1), fmt::format("dim[{}] is {}; one 3D volume is read, not a series", a + 1,
                                             h.get<std::int16_t>(kDim + 2 * (a + 1))));

  const detail::VoxelType type = voxel_type(h);
  const double unit = metres_per_unit(h);
  Vec3 pixdim;
  for (int a = 0; a < 3; ++a) {
    pixdim[a] = h.get<float>(kPixdim + 4 * (a + 1));
    if (!(std::isfinite(pixdim[a]) && pixdim[a] > 0.0))
      h.fail(kPixdim + 4 * (a + 1),
             fmt::format("pixdim[{}] (voxel spacing) is {}; it must be finite and positive", a + 1, pixdim[a]));
  }

  const auto sform_code = h.get<std::int16_t>(kSformCode);
  const auto qform_code = h.get<std::int16_t>(kQformCode);
  Mat3 axes;  // columns: world step per voxel along i, j, k, in file units
  Vec3 origin;
  if (sform_code > 0) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) axes(r, c) = h.get<float>(kSrow + 16 * r + 4 * c);
      origin[r] = h.get<float>(kSrow + 16 * r + 12);
    }
    if (!axes.allFinite() || !origin.allFinite()) h.fail(kSrow, "srow_x/y/z hold a value that is not finite");
    for (int c = 0; c < 3; ++c)
      if (!(axes.col(c).norm() > 0.0))
        h.fail(kSrow + 4 * c, fmt::format("the sform gives axis {} zero length", c + 1));
  } else if (qform_code > 0) {
    const double b = h.get<float>(kQuatern), c = h.get<float>(kQuatern + 4), d = h.get<float>(kQuatern + 8);
    const double a2 = 1.0 - (b * b + c * c + d * d);
    if (!std::isfinite(a2) || a2 < -1e-6) h.fail(kQuatern, "quatern_b/c/d is not part of a unit quaternion");
    const double a = std::sqrt(std::max(0.0, a2));
    Mat3 r;
    r << a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c),  //
        2 * (b * c + a * d), a * a + c * c - b * b - d * d, 2 * (c * d - a * b),   //
        2 * (b * d - a * c), 2 * (c * d + a * b), a * a + d * d - c * c - b * b;
    const double qfac = h.get<float>(kPixdim) < 0.0 ? -1.0 : 1.0;
    axes = r * Vec3(pixdim[0], pixdim[1], qfac * pixdim[2]).asDiagonal();
    for (int k = 0; k < 3; ++k) origin[k] = h.get<float>(kQoffset + 4 * k);
    if (!origin.allFinite()) h.fail(kQoffset, "qoffset_x/y/z is not finite");
  } else {
    axes = pixdim.asDiagonal();
    origin.setZero();
  }
  for (int c = 0; c < 3; ++c) {
    image.spacing[c] = axes.col(c).norm() * unit;
    image.direction.col(c) = axes.col(c).normalized();
  }
  image.origin = origin * unit;
  detail::check_geometry(image, "pixdim/sform");

  const float vox_offset = h.get<float>(kVoxOffset);
  if (!(vox_offset >= 348.0f) || vox_offset > static_cast<float>(data.size()))
    h.fail(kVoxOffset, fmt::format("vox_offset is {} in a file of {} bytes", vox_offset, data.size()));
  double slope = h.get<float>(kSclSlope), intercept = h.get<float>(kSclInter);
  if (slope == 0.0 || !std::isfinite(slope) || !std::isfinite(intercept)) {  // 0: no scaling (NIfTI-1)
    slope = 1.0;
    intercept = 0.0;
  }
  const auto offset = static_cast<std::size_t>(vox_offset);
  image.labels = detail::decode_labels(std::string_view(data).substr(offset), type, h.big_endian(),
                                       image.voxel_count(), file, offset, slope, intercept);
  return image;
}

void write_nifti(const std::filesystem::path& path, const LabelImage& image) {
  std::string out(352, '\0');
  auto put = [&](std::size_t offset, auto value) { std::memcpy(out.data() + offset, &value, sizeof(value)); };
  bool fits16 = true;
  for (std::int32_t l : image.labels) fits16 = fits16 && l >= -32768 && l <= 32767;
  put(0, std::int32_t{348});
  put(kDim, std::int16_t{3});
  for (int a = 0; a < 3; ++a) put(kDim + 2 * (a + 1), static_cast<std::int16_t>(image.size[a]));
  for (int a = 4; a < 8; ++a) put(kDim + 2 * a, std::int16_t{1});
  put(kDatatype, static_cast<std::int16_t>(fits16 ? 4 : 8));
  put(72, static_cast<std::int16_t>(fits16 ? 16 : 32));  // bitpix
  const Mat3 axes_mm = image.direction * image.spacing.asDiagonal() * 1e3;
  const Vec3 origin_mm = image.origin * 1e3;
  const bool rotation = (image.direction.transpose() * image.direction - Mat3::Identity()).norm() < 1e-9;
  float qfac = 1.0f;
  Mat3 r = image.direction;
  if (rotation && r.determinant() < 0.0) {
    qfac = -1.0f;
    r.col(2) = -r.col(2);
  }
  put(kPixdim, qfac);
  for (int a = 0; a < 3; ++a) put(kPixdim + 4 * (a + 1), static_cast<float>(image.spacing[a] * 1e3));
  put(kVoxOffset, 352.0f);
  put(kSclSlope, 1.0f);
  out[kXyztUnits] = 2;  // mm
  put(kSformCode, std::int16_t{2});  // aligned to something
  for (int row = 0; row < 3; ++row) {
    for (int c = 0; c < 3; ++c) put(kSrow + 16 * row + 4 * c, static_cast<float>(axes_mm(row, c)));
    put(kSrow + 16 * row + 12, static_cast<float>(origin_mm[row]));
  }
  if (rotation) {
    const Quat q(r);
    Quat qn = q.normalized();
    if (qn.w() < 0.0) qn.coeffs() = -qn.coeffs();
    put(kQformCode, std::int16_t{1});
    put(kQuatern, static_cast<float>(qn.x()));
    put(kQuatern + 4, static_cast<float>(qn.y()));
    put(kQuatern + 8, static_cast<float>(qn.z()));
    for (int k = 0; k < 3; ++k) put(kQoffset + 4 * k, static_cast<float>(origin_mm[k]));
  }
  std::memcpy(out.data() + kMagic, "n+1\0", 4);
  out.reserve(352 + image.labels.size() * (fits16 ? 2 : 4));
  for (std::int32_t l : image.labels) {
    if (fits16) {
      const auto v = static_cast<std::int16_t>(l);
      out.append(reinterpret_cast<const char*>(&v), 2);
    } else {
      out.append(reinterpret_cast<const char*>(&l), 4);
    }
  }
  const std::string name = path.filename().string();
  if (name.size() > 3 && name.compare(name.size() - 3, 3, ".gz") == 0) out = detail::gzip(out);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw InputError(SourceLocation{path.string(), {}, {}, {}}, "cannot write the file");
  const bool ok = std::fwrite(out.data(), 1, out.size(), f) == out.size();
  if (std::fclose(f) != 0 || !ok) throw InputError(SourceLocation{path.string(), {}, {}, {}}, "cannot write the file");
}

}  // namespace tactus::imaging
