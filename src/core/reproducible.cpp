#include "core/reproducible.hpp"

#include <Eigen/Core>

#include <mutex>

namespace tactus {

void fix_dense_blocking() {
  // Once per process: Eigen keeps the sizes in statics that its products read unguarded.
  static std::once_flag once;
  std::call_once(once, [] {
    constexpr std::ptrdiff_t kL1 = 32 * 1024, kL2 = 1024 * 1024, kL3 = 32 * 1024 * 1024;
    Eigen::setCpuCacheSizes(kL1, kL2, kL3);
  });
}

}  // namespace tactus
