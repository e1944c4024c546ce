#include "property_images/property_file.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/hdf5_file.hpp"

namespace tactus::property_images {

namespace {

using hdf5::fail;
using hdf5::Handle;

constexpr const char* kFormat = "tactus-property-images";
// Version 2 added the young_modulus and poisson_ratio channels; a version 1 file (the first
// six channels) reads with them 0: the body's material.
constexpr int kVersion = 2;
constexpr int kVersion1Channels = 6;
constexpr std::array<const char*, PropertyImages::kViewCount> kViewNames = {"+x", "-x", "+y", "-y", "+z", "-z"};

std::string channel_list(int count = kChannelCount) {
  return fmt::format("{}", fmt::join(kChannelNames.begin(), kChannelNames.begin() + count, ","));
}

}  // namespace

void write_property_images(const std::filesystem::path& path, const PropertyImages& images) {
  hdf5::QuietErrors quiet;
  const std::filesystem::path tmp = path.string() + ".tmp";
  hdf5::Writer w(path, "the property image file");
  {
    Handle file(H5Fcreate(tmp.string().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) fail(path, "cannot create the property image file");
    w.attribute(file, "format", kFormat);
    w.attribute(file, "version", H5T_NATIVE_INT, &kVersion);
    const std::uint64_t hash = images.mesh_hash();
    w.attribute(file, "mesh_hash", H5T_NATIVE_UINT64, &hash);
    w.attribute(file, "box_min", H5T_NATIVE_DOUBLE, images.box().min.data(), 3);
    w.attribute(file, "box_max", H5T_NATIVE_DOUBLE, images.box().max.data(), 3);
    const double pixel = images.pixel();
    w.attribute(file, "pixel", H5T_NATIVE_DOUBLE, &pixel);
    w.attribute(file, "channels", channel_list());
    w.attribute(file, "base", H5T_NATIVE_DOUBLE, images.base().values.data(), kChannelCount);
    Handle group(H5Gcreate2(file, "views", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    w.check(group.valid(), "views");
    for (int i = 0; i < PropertyImages::kViewCount; ++i) {
      const View& v = images.views()[i];
      Handle g(H5Gcreate2(group, kViewNames[i], H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
      w.check(g.valid(), kViewNames[i]);
      w.attribute(g, "axis", H5T_NATIVE_INT, &v.axis);
      w.attribute(g, "sign", H5T_NATIVE_INT, &v.sign);
      const auto h = static_cast<hsize_t>(v.height), wd = static_cast<hsize_t>(v.width);
      w.dataset(g, "depth", H5T_NATIVE_FLOAT, {h, wd}, v.depth.data());
      w.dataset(g, "values", H5T_NATIVE_FLOAT, {h, wd, kChannelCount}, v.values.data());
    }
    w.check(H5Fflush(file, H5F_SCOPE_GLOBAL) >= 0, "file");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) fail(path, "cannot move the finished property image file into place: " + ec.message());
}

PropertyImages read_property_images(const std::filesystem::path& path, std::optional<std::uint64_t> mesh_hash) {
  hdf5::QuietErrors quiet;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail(path, "file not found");
  if (H5Fis_hdf5(path.string().c_str()) <= 0) fail(path, "not an HDF5 file");
  Handle file(H5Fopen(path.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.valid()) fail(path, "cannot open the HDF5 file");
  hdf5::Reader r(path);
  if (r.text(file, "format") != kFormat) fail(path, "not a Tactus property image file");
  const int version = r.scalar<int>(file, "version", H5T_NATIVE_INT);
  if (version != kVersion && version != 1)
    fail(path, fmt::format("property image file version {} (this build reads versions 1 and {})", version, kVersion));
  const int channels = version == 1 ? kVersion1Channels : kChannelCount;
  if (r.text(file, "channels") != channel_list(channels))
    fail(path, fmt::format("channels are not '{}'", channel_list(channels)));
  const auto hash = r.scalar<std::uint64_t>(file, "mesh_hash", H5T_NATIVE_UINT64);
  if (mesh_hash && hash != *mesh_hash)
    fail(path, fmt::format("made for another mesh (mesh hash {:016x}, this body's is {:016x}): repaint or rebuild it",
                           hash, *mesh_hash));
  Aabb box;
  r.array(file, "box_min", H5T_NATIVE_DOUBLE, box.min.data(), 3);
  r.array(file, "box_max", H5T_NATIVE_DOUBLE, box.max.data(), 3);
  const auto pixel = r.scalar<double>(file, "pixel", H5T_NATIVE_DOUBLE);
  if (!box.min.allFinite() || !box.max.allFinite() || box.empty() || !std::isfinite(pixel) || !(pixel > 0.0) ||
      box.size().maxCoeff() / pixel > PropertyImages::kMaxResolution + 3)
    fail(path, "implausible box or pixel size");
  SurfaceProperties base;
  r.array(file, "base", H5T_NATIVE_DOUBLE, base.values.data(), static_cast<std::size_t>(channels));
  validate(base, SourceLocation{path.string() + " (base)", {}, {}, {}});

  Handle group(H5Gopen2(file, "views", H5P_DEFAULT), H5Gclose);
  if (!group.valid()) fail(path, "missing group 'views'");
  std::array<View, PropertyImages::kViewCount> views;
  for (int i = 0; i < PropertyImages::kViewCount; ++i) {
    View& v = views[i];
    Handle g(H5Gopen2(group, kViewNames[i], H5P_DEFAULT), H5Gclose);
    if (!g.valid()) fail(path, fmt::format("missing view '{}'", kViewNames[i]));
    v.axis = r.scalar<int>(g, "axis", H5T_NATIVE_INT);
    v.sign = r.scalar<int>(g, "sign", H5T_NATIVE_INT);
    if (v.axis != i / 2 || v.sign != (i % 2 == 0 ? 1 : -1))
      fail(path, fmt::format("view '{}' has axis {} and sign {}", kViewNames[i], v.axis, v.sign));
    v.u_axis = (v.axis + 1) % 3;
    v.v_axis = (v.axis + 2) % 3;
    const Vec3 size = box.size();
    v.width = static_cast<int>(std::ceil(size[v.u_axis] / pixel));
    v.height = static_cast<int>(std::ceil(size[v.v_axis] / pixel));
    const std::string name = fmt::format("views/{}", kViewNames[i]);
    const auto dims = r.dims(g, "depth", 2);
    if (dims[0] != static_cast<hsize_t>(v.height) || dims[1] != static_cast<hsize_t>(v.width))
      fail(path, fmt::format("{}/depth is {}×{}; the box and pixel size give {}×{}", name, dims[0], dims[1],
                             v.height, v.width));
    const auto n = static_cast<std::size_t>(v.width) * static_cast<std::size_t>(v.height);
    v.depth.resize(n);
    v.values.assign(n * kChannelCount, 0.0f);
    r.dataset(g, "depth", H5T_NATIVE_FLOAT, n, v.depth.data());
    const auto stored = static_cast<std::size_t>(channels);
    if (stored == kChannelCount) {
      r.dataset(g, "values", H5T_NATIVE_FLOAT, n * stored, v.values.data());
    } else {
      std::vector<float> old(n * stored);
      r.dataset(g, "values", H5T_NATIVE_FLOAT, n * stored, old.data());
      for (std::size_t p = 0; p < n; ++p)
        std::copy_n(old.begin() + static_cast<std::ptrdiff_t>(p * stored), stored,
                    v.values.begin() + static_cast<std::ptrdiff_t>(p * kChannelCount));
    }
    for (std::size_t p = 0; p < n; ++p) {
      const auto col = p % static_cast<std::size_t>(v.width), row = p / static_cast<std::size_t>(v.width);
      if (std::isnan(v.depth[p]) || v.depth[p] < 0.0f)
        fail(path, fmt::format("{} pixel (column {}, row {}): depth {} is not a distance", name, col, row, v.depth[p]));
      SurfaceProperties values;
      for (int c = 0; c < kChannelCount; ++c) values.values[c] = v.values[p * kChannelCount + c];
      validate(values, SourceLocation{fmt::format("{} {} pixel (column {}, row {})", path.string(), name, col, row),
                                      {}, {}, {}});
    }
  }
  return PropertyImages(box, pixel, hash, base, std::move(views));
}

}  // namespace tactus::property_images
