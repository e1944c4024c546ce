#pragma once
// Small wrappers over HDF5's C API for the files Tactus writes (configuration spaces,
// haptic property images): identifiers closed by RAII, HDF5's own error printing silenced,
// and every failure an InputError naming the file and the dataset or attribute. Header only:
// include it only where <hdf5.h> is on the include path (a folder that links HDF5).
#include <hdf5.h>

#include <fmt/format.h>

#include <filesystem>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"

namespace tactus::hdf5 {

/// Closes an HDF5 identifier with the right function.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() {
    if (id_ >= 0) closer_(id_);
  }
  operator hid_t() const { return id_; }  // NOLINT: used as the id it wraps
  [[nodiscard]] bool valid() const { return id_ >= 0; }

 private:
  hid_t id_;
  Closer closer_;
};

[[noreturn]] inline void fail(const std::filesystem::path& p, const std::string& why) {
  throw InputError(SourceLocation{p.string(), {}, {}, {}}, why);
}

/// Silences HDF5's own error printing while this lives (errors become InputErrors).
struct QuietErrors {
  H5E_auto2_t func = nullptr;
  void* data = nullptr;
  QuietErrors() {
    H5Eget_auto2(H5E_DEFAULT, &func, &data);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietErrors() { H5Eset_auto2(H5E_DEFAULT, func, data); }
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;
};

class Writer {
 public:
  Writer(const std::filesystem::path& path, std::string what) : path_(path), what_(std::move(what)) {}

  void dataset(hid_t loc, const char* name, hid_t type, std::initializer_list<hsize_t> dims, const void* data,
               bool compress = false) {
    std::vector<hsize_t> d(dims);
    Handle space(H5Screate_simple(static_cast<int>(d.size()), d.data(), nullptr), H5Sclose);
    Handle props(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
    bool any = true;
    for (auto x : d) any = any && x > 0;
    if (compress && any && d.size() == 2) {
      // One chunk per grid point: a point's shape is read without touching the others.
      const hsize_t chunk[2] = {1, d[1]};
      H5Pset_chunk(props, 2, chunk);
      if (H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0) {
        H5Pset_shuffle(props);
        H5Pset_deflate(props, 4);
      }
    }
    Handle set(H5Dcreate2(loc, name, type, space, H5P_DEFAULT, props, H5P_DEFAULT), H5Dclose);
    check(set.valid() && (!any || H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0), name);
  }

  void strings(hid_t loc, const char* name, const std::vector<std::string>& values) {
    std::vector<const char*> ptrs;
    for (const auto& s : values) ptrs.push_back(s.c_str());
    Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(type, H5T_VARIABLE);
    H5Tset_cset(type, H5T_CSET_UTF8);
    dataset(loc, name, type, {values.size()}, ptrs.data());
  }

  void attribute(hid_t loc, const char* name, hid_t type, const void* data, hsize_t n = 1) {
    Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
    Handle a(H5Acreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
    check(a.valid() && H5Awrite(a, type, data) >= 0, name);
  }
  void attribute(hid_t loc, const char* name, const std::string& value) {
    Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(type, H5T_VARIABLE);
    H5Tset_cset(type, H5T_CSET_UTF8);
    const char* p = value.c_str();
    attribute(loc, name, type, &p);
  }

  void check(bool ok, const char* what) const {
    if (!ok) fail(path_, "cannot write '" + std::string(what) + "' to " + what_);
  }

 private:
  std::filesystem::path path_;
  std::string what_;
};

class Reader {
 public:
  explicit Reader(const std::filesystem::path& path) : path_(path) {}

  /// The dataset's dimensions; fails unless its rank is `rank`.
  std::vector<hsize_t> dims(hid_t loc, const char* name, int rank) const {
    Handle set(H5Dopen2(loc, name, H5P_DEFAULT), H5Dclose);
    if (!set.valid()) fail(path_, fmt::format("missing dataset '{}'", name));
    Handle space(H5Dget_space(set), H5Sclose);
    if (H5Sget_simple_extent_ndims(space) != rank) fail(path_, fmt::format("dataset '{}' has the wrong rank", name));
    std::vector<hsize_t> d(static_cast<std::size_t>(rank));
    H5Sget_simple_extent_dims(space, d.data(), nullptr);
    return d;
  }

  /// Reads a dataset of exactly `count` values of `type` into out.
  void dataset(hid_t loc, const char* name, hid_t type, std::size_t count, void* out) const {
    Handle set(H5Dopen2(loc, name, H5P_DEFAULT), H5Dclose);
    if (!set.valid()) fail(path_, fmt::format("missing dataset '{}'", name));
    Handle space(H5Dget_space(set), H5Sclose);
    const auto n = H5Sget_simple_extent_npoints(space);
    if (n < 0 || static_cast<std::size_t>(n) != count)
      fail(path_, fmt::format("dataset '{}' has {} values, expected {}", name, n, count));
    if (count > 0 && H5Dread(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) < 0)
      fail(path_, fmt::format("cannot read dataset '{}'", name));
  }

  std::vector<std::string> strings(hid_t loc, const char* name, std::size_t count) const {
    Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(type, H5T_VARIABLE);
    H5Tset_cset(type, H5T_CSET_UTF8);
    std::vector<char*> ptrs(count, nullptr);
    dataset(loc, name, type, count, ptrs.data());
    std::vector<std::string> out;
    for (char* p : ptrs) out.emplace_back(p ? p : "");
    if (count > 0) {
      Handle set(H5Dopen2(loc, name, H5P_DEFAULT), H5Dclose);
      Handle space(H5Dget_space(set), H5Sclose);
      H5Dvlen_reclaim(type, space, H5P_DEFAULT, ptrs.data());
    }
    return out;
  }

  template <class T>
  T scalar(hid_t loc, const char* name, hid_t type) const {
    T v{};
    array(loc, name, type, &v, 1);
    return v;
  }
  void array(hid_t loc, const char* name, hid_t type, void* out, hsize_t n) const {
    Handle a(H5Aopen(loc, name, H5P_DEFAULT), H5Aclose);
    if (!a.valid()) fail(path_, fmt::format("missing attribute '{}'", name));
    Handle space(H5Aget_space(a), H5Sclose);
    if (H5Sget_simple_extent_npoints(space) != static_cast<hssize_t>(n))
      fail(path_, fmt::format("attribute '{}' has the wrong size", name));
    if (H5Aread(a, type, out) < 0) fail(path_, fmt::format("cannot read attribute '{}'", name));
  }
  std::string text(hid_t loc, const char* name) const {
    Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(type, H5T_VARIABLE);
    H5Tset_cset(type, H5T_CSET_UTF8);
    char* p = nullptr;
    array(loc, name, type, &p, 1);
    std::string s = p ? p : "";
    H5free_memory(p);
    return s;
  }

 private:
  std::filesystem::path path_;
};

}  // namespace tactus::hdf5
