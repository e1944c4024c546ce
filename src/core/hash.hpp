#pragma once
// 64-bit FNV-1a: the identity of a mesh or a model that a file was built for (configuration
// spaces, impostor caches, property images), cheap and stable across machines.
#include <cstddef>
#include <cstdint>

namespace tactus {

class Fnv1a {
 public:
  void add(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) value_ = (value_ ^ p[i]) * 1099511628211ull;
  }
  template <class T>
  void add_value(const T& v) {
    add(&v, sizeof v);
  }
  [[nodiscard]] std::uint64_t value() const { return value_; }

 private:
  std::uint64_t value_ = 14695981039346656037ull;
};

}  // namespace tactus
