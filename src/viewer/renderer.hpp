#pragma once
// Draws a FrameView with OpenGL 3.3 core: smooth-shaded surfaces with contact pressure in
// false colour, spheres, force arrows, a floor, one directional light with a shadow map as
// depth cue; translucency and wireframe on request. The same code draws the window and the
// offscreen snapshots, so both look alike.
#include <cstdint>
#include <initializer_list>
#include <unordered_map>
#include <vector>

#include "viewer/camera.hpp"
#include "viewer/frame.hpp"
#include "viewer/gl.hpp"

namespace tactus::viewer {

class Renderer {
 public:
  /// Needs a current OpenGL 3.3 core context; throws std::runtime_error when a shader or
  /// the shadow map cannot be built (the message says which). `shadow_map_size`: texels a
  /// side of the shadow map (256 to 4096), whose every texel a frame clears and fills.
  explicit Renderer(int shadow_map_size = 2048);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Draws into the framebuffer bound now, over a width × height viewport.
  void render(const FrameView& frame, const OrbitCamera& camera, const ViewOptions& options, int width, int height);

 private:
  struct Vertex {
    float position[3];
    float normal[3];
    float colour[4];
  };
  struct Batches {
    std::vector<Vertex> opaque, translucent, wire, lines;
    /// Opaque surfaces drawn behind those they coincide with (SurfaceView::recessed).
    std::vector<Vertex> recessed;
    /// Lines drawn over everything: a contact's constraint plane lies where the haptic loop
    /// has the tissue, which between simulation steps may be under the shown surface.
    std::vector<Vertex> overlay;
  };
  /// `extent`: the frame's largest side [m], which sets the least width a needle is drawn.
  /// Surfaces marked in `kept` are left out (drawn from the static cache).
  void build(const FrameView& frame, const ViewOptions& options, double extent, const std::vector<bool>& kept,
             Batches& out) const;
  /// Whether `s` may be drawn from the static cache this frame: marked static, opaque, not
  /// recessed, no wireframe, one colour (its pressure is drawn over it).
  [[nodiscard]] static bool cacheable(const SurfaceView& s, const ViewOptions& options);
  /// The cache entry of a static surface, (re)built when missing or when its colour changed.
  struct StaticSurface {
    GLuint vao = 0, vbo = 0;
    GLsizei count = 0;
    Colour colour = Colour::Zero();
    std::vector<Vec3> normals;    ///< its smooth normals, for the contact drawn over it
    std::uint64_t last_used = 0;  ///< the frame it was last drawn in
  };
  const StaticSurface& keep(const SurfaceView& s, const ViewOptions& options, double full_scale);
  void draw_kept();
  /// Where a batch lies in the frame's vertex buffer.
  struct Range {
    GLint first = 0;
    GLsizei count = 0;
  };
  /// Tells the bound vertex array how a Vertex lies in the bound buffer.
  static void describe_vertices();
  /// Sends the batches as one buffer; ranges_ then says where each lies, in order.
  void upload(std::initializer_list<const std::vector<Vertex>*> batches);
  void draw(const Range& range, GLenum mode = GL_TRIANGLES);

  GLuint shaded_ = 0, depth_ = 0;  // programs
  GLuint vao_ = 0, vbo_ = 0;
  int shadow_size_;
  GLuint shadow_fbo_ = 0, shadow_texture_ = 0;
  std::vector<Vec3> unit_sphere_;  ///< triangle soup of a unit icosphere (positions = normals)
  Aabb floor_box_;                 ///< the scene's bounds the floor was sized from (kept steady)
  bool floor_sized_ = false;
  std::vector<Vertex> all_;     ///< the frame's batches end to end (kept for its capacity)
  std::vector<Range> ranges_;
  std::unordered_map<const void*, StaticSurface> kept_;  ///< by SurfaceView::static_id
  std::vector<const StaticSurface*> kept_now_;             ///< drawn this frame
  std::uint64_t frame_ = 0;
};

/// The bound read framebuffer's pixels as 8-bit RGB, rows top to bottom.
std::vector<std::uint8_t> read_rgb(int width, int height);

}  // namespace tactus::viewer
