#pragma once
// A single-sampled colour + depth framebuffer the scene is drawn into at a fraction of the
// window's size, then stretched over the window with linear filtering (the resolution the
// frame budget allows; viewer/frame_budget.hpp). Also where a level's draw time is measured.
#include "viewer/gl.hpp"

namespace tactus::viewer {

class SceneTarget {
 public:
  SceneTarget() = default;
  ~SceneTarget();
  SceneTarget(const SceneTarget&) = delete;
  SceneTarget& operator=(const SceneTarget&) = delete;

  /// Binds a width × height target for drawing, made again when the size changes. Needs a
  /// current context; throws std::runtime_error when the driver refuses the size.
  void bind(int width, int height);
  /// Copies the target over the whole width × height of framebuffer `target`, filtered.
  void stretch_to(GLuint target, int width, int height) const;
  /// Frees the framebuffer (while the context is still current).
  void release();

 private:
  int width_ = 0, height_ = 0;
  GLuint framebuffer_ = 0, colour_ = 0, depth_ = 0;
};

}  // namespace tactus::viewer
