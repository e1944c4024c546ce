#include "viewer/renderer.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "mesh/generators.hpp"

namespace tactus::viewer {
namespace {


/// Frames a cached static surface stays after it was last drawn (a few seconds at 60 Hz).
constexpr std::uint64_t kKeepFrames = 240;

const char* const kShadedVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec4 aColour;
uniform mat4 uViewProjection;
uniform mat4 uLightViewProjection;
out vec3 vPosition;
out vec3 vNormal;
out vec4 vColour;
out vec4 vLightPosition;
void main() {
  vPosition = aPosition;
  vNormal = aNormal;
  vColour = aColour;
  vLightPosition = uLightViewProjection * vec4(aPosition, 1.0);
  gl_Position = uViewProjection * vec4(aPosition, 1.0);
}
)";

const char* const kShadedFragment = R"(#version 330 core
in vec3 vPosition;
in vec3 vNormal;
in vec4 vColour;
in vec4 vLightPosition;
uniform vec3 uLightDirection;
uniform vec3 uEye;
uniform sampler2DShadow uShadow;
uniform int uShadows;
uniform int uSoftShadows;
uniform int uUnlit;
out vec4 outColour;
float lit_fraction(vec3 n) {
  vec3 p = vLightPosition.xyz / vLightPosition.w * 0.5 + 0.5;
  if (p.z > 1.0) return 1.0;
  float bias = max(0.004 * (1.0 - dot(n, uLightDirection)), 0.001);
  if (uSoftShadows == 0) return texture(uShadow, vec3(p.xy, p.z - bias));  // one tap, filtered 2 x 2
  vec2 texel = 1.0 / vec2(textureSize(uShadow, 0));
  float sum = 0.0;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y) sum += texture(uShadow, vec3(p.xy + vec2(x, y) * texel, p.z - bias));
  return sum / 9.0;
}
void main() {
  if (uUnlit == 1) {
    outColour = vColour;
    return;
  }
  vec3 n = normalize(vNormal);
  if (!gl_FrontFacing) n = -n;  // open sheets are seen from both sides
  vec3 v = normalize(uEye - vPosition);
  float diffuse = max(dot(n, uLightDirection), 0.0);
  float specular = pow(max(dot(n, normalize(uLightDirection + v)), 0.0), 40.0) * 0.2;
  float light = uShadows == 1 ? mix(0.35, 1.0, lit_fraction(n)) : 1.0;
  vec3 c = vColour.rgb * (0.3 + 0.7 * diffuse * light) + vec3(specular * light);
  if (!gl_FrontFacing) c *= 0.7;  // a sheet's back (a fabric's other side) darker than its front
  outColour = vec4(c, vColour.a);
}
)";

const char* const kDepthVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
uniform mat4 uLightViewProjection;
void main() { gl_Position = uLightViewProjection * vec4(aPosition, 1.0); }
)";

const char* const kDepthFragment = R"(#version 330 core
void main() {}
)";

GLuint compile(GLenum kind, const char* source, const char* what) {
  const GLuint s = glCreateShader(kind);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    throw std::runtime_error(std::string("viewer: the ") + what + " shader does not compile: " + log);
  }
  return s;
}

GLuint link(const char* vertex, const char* fragment, const char* what) {
  const GLuint v = compile(GL_VERTEX_SHADER, vertex, what), f = compile(GL_FRAGMENT_SHADER, fragment, what);
  const GLuint p = glCreateProgram();
  glAttachShader(p, v);
  glAttachShader(p, f);
  glLinkProgram(p);
  glDeleteShader(v);
  glDeleteShader(f);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    glDeleteProgram(p);
    throw std::runtime_error(std::string("viewer: the ") + what + " program does not link: " + log);
  }
  return p;
}

Mat4f look_at(const Vec3& eye, const Vec3& target, const Vec3& up_hint) {
  const Vec3 f = (target - eye).normalized();
  Vec3 r = f.cross(up_hint);
  if (r.norm() < 1e-9) r = f.cross(Vec3::UnitY());
  r.normalize();
  const Vec3 u = r.cross(f);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = r.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -r.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m.cast<float>();
}

Mat4f orthographic(double half, double near, double far) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(0, 0) = 1.0 / half;
  m(1, 1) = 1.0 / half;
  m(2, 2) = -2.0 / (far - near);
  m(2, 3) = -(far + near) / (far - near);
  return m.cast<float>();
}

void set_matrix(GLuint program, const char* name, const Mat4f& m) {
  glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_FALSE, m.data());
}

/// Appends one vertex; colour with alpha.
template <class V>
void push(std::vector<V>& out, const Vec3& p, const Vec3& n, const Colour& c, double alpha) {
  out.push_back({{static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())},
                 {static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z())},
                 {static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z()), static_cast<float>(alpha)}});
}

/// A cylinder from a to b (radius r) or a cone (r at a, 0 at b), as triangles.
template <class V>
void push_cone(std::vector<V>& out, const Vec3& a, const Vec3& b, double ra, double rb, const Colour& c) {
  constexpr int kSegments = 16;
  const Vec3 axis = (b - a).normalized();
  Vec3 u = axis.cross(std::abs(axis.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX()).normalized();
  const Vec3 w = axis.cross(u);
  const double slope = (ra - rb) / std::max((b - a).norm(), 1e-12);
  for (int i = 0; i < kSegments; ++i) {
    const double t0 = 2.0 * std::numbers::pi * i / kSegments, t1 = 2.0 * std::numbers::pi * (i + 1) / kSegments;
    const Vec3 d0 = std::cos(t0) * u + std::sin(t0) * w, d1 = std::cos(t1) * u + std::sin(t1) * w;
    const Vec3 n0 = (d0 + slope * axis).normalized(), n1 = (d1 + slope * axis).normalized();
    push(out, a + ra * d0, n0, c, 1.0);
    push(out, a + ra * d1, n1, c, 1.0);
    push(out, b + rb * d1, n1, c, 1.0);
    push(out, a + ra * d0, n0, c, 1.0);
    push(out, b + rb * d1, n1, c, 1.0);
    push(out, b + rb * d0, n0, c, 1.0);
    // The base disc.
    push(out, a, -axis, c, 1.0);
    push(out, a + ra * d1, -axis, c, 1.0);
    push(out, a + ra * d0, -axis, c, 1.0);
  }
}

}  // namespace

void Renderer::describe_vertices() {
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, position)));
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, normal)));
  glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, colour)));
  for (GLuint i = 0; i < 3; ++i) glEnableVertexAttribArray(i);
}

Renderer::Renderer(int shadow_map_size) : shadow_size_(std::clamp(shadow_map_size, 256, 4096)) {
  shaded_ = link(kShadedVertex, kShadedFragment, "shading");
  depth_ = link(kDepthVertex, kDepthFragment, "shadow depth");
  glGenVertexArrays(1, &vao_);
  glGenBuffers(1, &vbo_);
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  describe_vertices();
  glBindVertexArray(0);

  glGenTextures(1, &shadow_texture_);
  glBindTexture(GL_TEXTURE_2D, shadow_texture_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, shadow_size_, shadow_size_, 0, GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
  const float border[4] = {1.0f, 1.0f, 1.0f, 1.0f};
  glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, border);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glGenFramebuffers(1, &shadow_fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, shadow_texture_, 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (status != GL_FRAMEBUFFER_COMPLETE) throw std::runtime_error("viewer: the shadow map framebuffer is incomplete");

  const mesh::TriMesh sphere = mesh::sphere(1.0, 3);
  for (const mesh::Triangle& t : sphere.triangles)
    for (const mesh::Index v : t) unit_sphere_.push_back(sphere.vertices[static_cast<std::size_t>(v)].normalized());
}

Renderer::~Renderer() {
  for (auto& [id, e] : kept_) {
    glDeleteBuffers(1, &e.vbo);
    glDeleteVertexArrays(1, &e.vao);
  }
  glDeleteFramebuffers(1, &shadow_fbo_);
  glDeleteTextures(1, &shadow_texture_);
  glDeleteBuffers(1, &vbo_);
  glDeleteVertexArrays(1, &vao_);
  glDeleteProgram(shaded_);
  glDeleteProgram(depth_);
}

namespace {

bool valid_triangle(const SurfaceView& s, const mesh::Triangle& t) {
  return std::all_of(t.begin(), t.end(), [&](mesh::Index v) { return v >= 0 && static_cast<std::size_t>(v) < s.positions.size(); });
}

/// Smooth vertex normals: area-weighted face normals (not normalized).
std::vector<Vec3> smooth_normals(const SurfaceView& s) {
  std::vector<Vec3> normals(s.positions.size(), Vec3::Zero());
  for (const mesh::Triangle& t : s.triangles) {
    if (!valid_triangle(s, t)) continue;
    const Vec3& a = s.positions[static_cast<std::size_t>(t[0])];
    const Vec3 n = (s.positions[static_cast<std::size_t>(t[1])] - a).cross(s.positions[static_cast<std::size_t>(t[2])] - a);
    for (const mesh::Index v : t) normals[static_cast<std::size_t>(v)] += n;
  }
  return normals;
}

bool pressed(const SurfaceView& s, const mesh::Triangle& t) {
  return std::any_of(t.begin(), t.end(), [&](mesh::Index v) { return s.pressure[static_cast<std::size_t>(v)] > 0.0; });
}

/// A surface's triangles as vertices with `normals`, pressure blended over the colour; only
/// those with a pressed vertex when `only_pressed` (the contact drawn over a kept surface).
template <class V>
void append_surface(const SurfaceView& s, const std::vector<Vec3>& normals, const ViewOptions& options,
                    double pressure_full_scale, double alpha, std::vector<V>& target, std::vector<V>* wire,
                    bool only_pressed = false) {
  const bool pressure = options.show_pressure && s.pressure.size() == s.positions.size();
  if (only_pressed && !pressure) return;
  const bool per_triangle = s.triangle_colours.size() == s.triangles.size();
  for (std::size_t ti = 0; ti < s.triangles.size(); ++ti) {
    const mesh::Triangle& t = s.triangles[ti];
    if (!valid_triangle(s, t) || (only_pressed && !pressed(s, t))) continue;
    for (const mesh::Index vi : t) {
      const auto v = static_cast<std::size_t>(vi);
      Colour c = per_triangle ? s.triangle_colours[ti] : s.colour;
      if (pressure && s.pressure[v] > 0.0) {
        const double fraction = s.pressure[v] / pressure_full_scale;
        // Fully false-coloured from 3 % of full scale on, so light touches show too.
        const double w = std::clamp(fraction / 0.03, 0.0, 1.0);
        c = (1.0 - w) * c + w * pressure_colour(fraction);
      }
      push(target, s.positions[v], normals[v].normalized(), c, alpha);
      if (wire) push(*wire, s.positions[v], Vec3::UnitZ(), Colour(0.1, 0.1, 0.12), 1.0);
    }
  }
}

}  // namespace

bool Renderer::cacheable(const SurfaceView& s, const ViewOptions& options) {
  if (!s.static_id || s.recessed || options.wireframe || (options.reveal && s.translucent_when_revealing)) return false;
  return s.triangle_colours.empty();
}

const Renderer::StaticSurface& Renderer::keep(const SurfaceView& s, const ViewOptions& options, double full_scale) {
  StaticSurface& e = kept_[s.static_id];
  if (!e.vbo || !e.colour.isApprox(s.colour, 0.0)) {
    e.normals = smooth_normals(s);
    SurfaceView untouched = s;
    untouched.pressure.clear();  // the contact is drawn over it, each frame
    std::vector<Vertex> vertices;
    append_surface(untouched, e.normals, options, full_scale, 1.0, vertices, static_cast<std::vector<Vertex>*>(nullptr));
    if (!e.vao) {
      glGenVertexArrays(1, &e.vao);
      glGenBuffers(1, &e.vbo);
      glBindVertexArray(e.vao);
      glBindBuffer(GL_ARRAY_BUFFER, e.vbo);
      describe_vertices();
    }
    glBindBuffer(GL_ARRAY_BUFFER, e.vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(Vertex)), vertices.data(), GL_STATIC_DRAW);
    e.count = static_cast<GLsizei>(vertices.size());
    e.colour = s.colour;
  }
  e.last_used = frame_;
  return e;
}

void Renderer::draw_kept() {
  for (const StaticSurface* e : kept_now_) {
    glBindVertexArray(e->vao);
    glDrawArrays(GL_TRIANGLES, 0, e->count);
  }
  glBindVertexArray(vao_);
}

void Renderer::build(const FrameView& frame, const ViewOptions& options, double extent, const std::vector<bool>& kept,
                     Batches& out) const {
  for (std::size_t i = 0; i < frame.surfaces.size(); ++i) {
    if (i < kept.size() && kept[i]) continue;
    const SurfaceView& s = frame.surfaces[i];
    const bool translucent = options.reveal && s.translucent_when_revealing;
    std::vector<Vertex>& target = translucent ? out.translucent : s.recessed ? out.recessed : out.opaque;
    append_surface(s, smooth_normals(s), options, frame.pressure_full_scale, translucent ? 0.35 : 1.0, target,
                   options.wireframe ? &out.wire : nullptr);
  }
  for (const SphereView& s : frame.spheres) {
    if (s.subsurface && !options.reveal) continue;
    std::vector<Vertex>& target = s.opacity < 1.0 ? out.translucent : out.opaque;
    for (const Vec3& n : unit_sphere_) push(target, s.centre + s.radius * n, n, s.colour, s.opacity);
  }
  for (const NeedleView& n : frame.needles) {
    if (!n.tip.allFinite() || !n.axis.allFinite() || n.axis.norm() < 0.5 || !(n.length > 0.0)) continue;
    // At least a few pixels wide at the scene's scale, or a fine needle vanishes.
    const double r = std::max(n.radius, 0.0025 * extent);
    const Vec3 axis = n.axis.normalized();
    const Vec3 hub_end = n.tip - n.length * axis, hub = hub_end + std::min(0.15 * n.length, 0.012) * axis;
    const Vec3 bevel = n.tip - std::min(6.0 * r, 0.2 * n.length) * axis;
    push_cone(out.opaque, hub_end, hub, 3.0 * r, 3.0 * r, Colour(0.25, 0.55, 0.85));
    push_cone(out.opaque, hub, bevel, r, r, n.colour);
    push_cone(out.opaque, bevel, n.tip, r, 0.0, n.colour);
  }
  if (options.show_forces)
    for (const ArrowView& a : frame.arrows) {
      const double length = a.length();
      if (!(length > 1e-6) || !std::isfinite(length)) continue;
      const Vec3 dir = a.force.normalized();
      const double radius = std::max(0.04 * length, 4e-4);
      const Vec3 neck = a.origin + dir * length * 0.75, tip = a.origin + dir * length;
      push_cone(out.opaque, a.origin, neck, radius, radius, a.colour);
      push_cone(out.opaque, neck, tip, 2.2 * radius, 0.0, a.colour);
    }
  if (options.show_planes)
    for (const QuadView& q : frame.quads) {
      if (!q.normal.allFinite() || q.normal.norm() < 0.5) continue;
      const Vec3 n = q.normal.normalized();
      const Vec3 u = n.unitOrthogonal() * q.half, w = n.cross(u);
      const Vec3 c00 = q.centre - u - w, c10 = q.centre + u - w, c11 = q.centre + u + w, c01 = q.centre - u + w;
      for (const Vec3& p : {c00, c10, c11, c00, c11, c01}) push(out.translucent, p, n, q.colour, q.opacity);
      // Its outline and normal, so that it shows edge-on too.
      for (const Vec3& p : {c00, c10, c10, c11, c11, c01, c01, c00}) push(out.overlay, p, n, q.colour, 1.0);
      push(out.overlay, q.centre, n, q.colour, 1.0);
      push(out.overlay, q.centre + n * q.half, n, q.colour, 1.0);
    }
  if (options.show_bvh)
    for (const BoxView& b : frame.boxes) {
      const auto corner = [&](int i) {
        return Vec3(i & 1 ? b.hi.x() : b.lo.x(), i & 2 ? b.hi.y() : b.lo.y(), i & 4 ? b.hi.z() : b.lo.z());
      };
      // The 12 edges: corners differing in one coordinate bit.
      for (int i = 0; i < 8; ++i)
        for (int bit = 1; bit < 8; bit <<= 1)
          if (!(i & bit)) {
            push(out.lines, corner(i), Vec3::UnitZ(), b.colour, 1.0);
            push(out.lines, corner(i | bit), Vec3::UnitZ(), b.colour, 1.0);
          }
    }
}

void Renderer::upload(std::initializer_list<const std::vector<Vertex>*> batches) {
  all_.clear();
  ranges_.clear();
  for (const std::vector<Vertex>* b : batches) {
    ranges_.push_back({static_cast<GLint>(all_.size()), static_cast<GLsizei>(b->size())});
    all_.insert(all_.end(), b->begin(), b->end());
  }
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(all_.size() * sizeof(Vertex)), all_.data(), GL_STREAM_DRAW);
}

void Renderer::draw(const Range& range, GLenum mode) {
  if (range.count > 0) glDrawArrays(mode, range.first, range.count);
}

void Renderer::render(const FrameView& frame, const OrbitCamera& camera, const ViewOptions& options, int width,
                      int height) {
  GLint target_fbo = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target_fbo);

  // A floor under the scene receives the shadows; sized once so it does not breathe.
  const Aabb box = frame_bounds(frame);
  // Static surfaces (rigid objects' levels) come from the cache; the rest is built anew.
  ++frame_;
  kept_now_.clear();
  std::vector<bool> kept(frame.surfaces.size(), false);
  std::vector<Vertex> contact;  // the pressed triangles of kept surfaces, drawn over them
  for (std::size_t i = 0; i < frame.surfaces.size(); ++i)
    if (cacheable(frame.surfaces[i], options)) {
      const StaticSurface& e = keep(frame.surfaces[i], options, frame.pressure_full_scale);
      kept_now_.push_back(&e);
      kept[i] = true;
      append_surface(frame.surfaces[i], e.normals, options, frame.pressure_full_scale, 1.0, contact,
                     static_cast<std::vector<Vertex>*>(nullptr), true);
    }
  // Levels not drawn for a while (the viewer chose others) give their memory back.
  for (auto it = kept_.begin(); it != kept_.end();) {
    if (frame_ - it->second.last_used > kKeepFrames) {
      glDeleteBuffers(1, &it->second.vbo);
      glDeleteVertexArrays(1, &it->second.vao);
      it = kept_.erase(it);
    } else {
      ++it;
    }
  }
  Batches batches;
  build(frame, options, std::max((box.max - box.min).maxCoeff(), 1e-3), kept, batches);
  if (!floor_sized_) {
    floor_box_ = box;
    floor_sized_ = true;
  }
  const Vec3 size = floor_box_.max - floor_box_.min;
  const double extent = std::max({size.x(), size.y(), size.z(), 1e-3});
  const Vec3 centre = 0.5 * (floor_box_.min + floor_box_.max);
  const double floor_z = floor_box_.min.z() - 0.15 * extent;
  const double half = 0.9 * extent;
  // The floor only receives shadows: it stays out of the shadow map, whose every texel it
  // would otherwise fill.
  std::vector<Vertex> floor_quad;
  {
    const Colour grey(0.55, 0.56, 0.58);
    const Vec3 n = Vec3::UnitZ();
    const Vec3 c00(centre.x() - half, centre.y() - half, floor_z), c10(centre.x() + half, centre.y() - half, floor_z),
        c11(centre.x() + half, centre.y() + half, floor_z), c01(centre.x() - half, centre.y() + half, floor_z);
    for (const Vec3& p : {c00, c10, c11, c00, c11, c01}) push(floor_quad, p, n, grey, 1.0);
  }

  // The light: from above, a little to the side, covering the floor and everything on it.
  const Vec3 light_dir = Vec3(0.35, 0.25, 1.0).normalized();
  const double light_radius = std::max((box.max - box.min).norm(), 2.0 * half * std::numbers::sqrt2) * 0.75;
  const Vec3 light_target(centre.x(), centre.y(), 0.5 * (floor_z + box.max.z()));
  const Mat4f light_vp = orthographic(light_radius, 0.0, 4.0 * light_radius) *
                         look_at(light_target + 2.0 * light_radius * light_dir, light_target, Vec3::UnitZ());

  // One upload a frame: a software renderer waits for the draws that read a buffer before it
  // replaces the buffer's data, so uploading each batch before its draw would serialize them.
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  upload({&floor_quad, &batches.opaque, &batches.recessed, &batches.wire, &batches.lines, &batches.translucent,
          &batches.overlay, &contact});
  const Range floor_range = ranges_[0], opaque = ranges_[1], recessed = ranges_[2], wire = ranges_[3],
              lines = ranges_[4], translucent = ranges_[5], overlay = ranges_[6], pressed_range = ranges_[7];
  const auto draw_recessed = [&] {
    // Pushed back in depth, so that a layer on its boundary wins every pixel they share.
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(2.0f, 8.0f);
    draw(recessed);
    glDisable(GL_POLYGON_OFFSET_FILL);
  };
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);

  if (options.shadows) {
    glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_);
    glViewport(0, 0, shadow_size_, shadow_size_);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(depth_);
    set_matrix(depth_, "uLightViewProjection", light_vp);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.5f, 2.0f);
    draw(opaque);
    draw(recessed);
    draw_kept();
    glDisable(GL_POLYGON_OFFSET_FILL);
    glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(target_fbo));
  }

  glViewport(0, 0, width, height);
  glClearColor(0.16f, 0.17f, 0.2f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glUseProgram(shaded_);
  set_matrix(shaded_, "uViewProjection", camera.projection(static_cast<double>(width) / std::max(height, 1)) * camera.view());
  set_matrix(shaded_, "uLightViewProjection", light_vp);
  glUniform3f(glGetUniformLocation(shaded_, "uLightDirection"), static_cast<float>(light_dir.x()),
              static_cast<float>(light_dir.y()), static_cast<float>(light_dir.z()));
  const Vec3 eye = camera.eye();
  glUniform3f(glGetUniformLocation(shaded_, "uEye"), static_cast<float>(eye.x()), static_cast<float>(eye.y()),
              static_cast<float>(eye.z()));
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, shadow_texture_);
  glUniform1i(glGetUniformLocation(shaded_, "uShadow"), 0);
  glUniform1i(glGetUniformLocation(shaded_, "uShadows"), options.shadows ? 1 : 0);
  glUniform1i(glGetUniformLocation(shaded_, "uSoftShadows"), options.soft_shadows ? 1 : 0);
  glUniform1i(glGetUniformLocation(shaded_, "uUnlit"), 0);
  if (options.floor) draw(floor_range);
  draw(opaque);
  draw_kept();
  if (pressed_range.count > 0) {
    // The contact's colours over a kept surface: the same triangles, pulled forward in depth.
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(-1.0f, -2.0f);
    draw(pressed_range);
    glDisable(GL_POLYGON_OFFSET_FILL);
  }
  draw_recessed();

  if (wire.count > 0) {
    glUniform1i(glGetUniformLocation(shaded_, "uUnlit"), 1);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glEnable(GL_POLYGON_OFFSET_LINE);
    glPolygonOffset(-1.0f, -1.0f);
    draw(wire);
    glDisable(GL_POLYGON_OFFSET_LINE);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glUniform1i(glGetUniformLocation(shaded_, "uUnlit"), 0);
  }

  if (lines.count > 0) {
    glUniform1i(glGetUniformLocation(shaded_, "uUnlit"), 1);
    draw(lines, GL_LINES);
    glUniform1i(glGetUniformLocation(shaded_, "uUnlit"), 0);
  }

  if (translucent.count > 0) {
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    draw(translucent);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
  }
  if (overlay.count > 0) {
    glUniform1i(glGetUniformLocation(shaded_, "uUnlit"), 1);
    glDisable(GL_DEPTH_TEST);
    draw(overlay, GL_LINES);
    glEnable(GL_DEPTH_TEST);
    glUniform1i(glGetUniformLocation(shaded_, "uUnlit"), 0);
  }

  glBindVertexArray(0);
  glUseProgram(0);
}

std::vector<std::uint8_t> read_rgb(int width, int height) {
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  // OpenGL's rows run bottom to top; images run top to bottom.
  const std::size_t row = static_cast<std::size_t>(width) * 3;
  std::vector<std::uint8_t> flipped(pixels.size());
  for (int y = 0; y < height; ++y)
    std::copy_n(pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * row), row,
                flipped.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(height - 1 - y) * row));
  return flipped;
}

}  // namespace tactus::viewer
