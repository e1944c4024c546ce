#pragma once
// Rendering without a window: an OpenGL 3.3 core context on EGL's surfaceless platform
// (Mesa's llvmpipe when there is no GPU) and a multisampled framebuffer to draw into.
#include <cstdint>
#include <vector>

#include "viewer/gl.hpp"

namespace tactus::viewer {

/// Makes a context current on this thread for its lifetime. Throws std::runtime_error
/// saying what is missing when EGL cannot give one.
class OffscreenContext {
 public:
  OffscreenContext();
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

 private:
  void* display_ = nullptr;
  void* context_ = nullptr;
};

/// A width × height colour + depth target, 4× multisampled, resolved when read.
class OffscreenTarget {
 public:
  /// Needs a current context; throws std::runtime_error for sizes the driver refuses.
  OffscreenTarget(int width, int height);
  ~OffscreenTarget();
  OffscreenTarget(const OffscreenTarget&) = delete;
  OffscreenTarget& operator=(const OffscreenTarget&) = delete;

  /// Binds the multisampled framebuffer for drawing.
  void bind() const;
  /// Resolves the samples and returns 8-bit RGB, rows top to bottom.
  [[nodiscard]] std::vector<std::uint8_t> read() const;
  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }

 private:
  int width_, height_;
  GLuint multisampled_ = 0, resolved_ = 0;
  GLuint colour_ms_ = 0, depth_ms_ = 0, colour_ = 0;
};

}  // namespace tactus::viewer
