#pragma once
// Haptic property images (seed 001, second chapter, Ryu & Kim): an object's surface material
// stored per pixel in six orthogonal depth images, one looking in from each face of its
// bounding box (±x, ±y, ±z). A pixel holds the depth of the first surface its ray meets and
// the material there: stiffness, static and kinetic friction, damping, roughness amplitude
// and wavelength, and the elastic constants (E, ν) that a Hertz finger presses against. A contact point takes the material of the view that sees it best (by its
// normal, the first view whose depth agrees with the point), bilinearly filtered. Painting
// writes every pixel whose surface point lies within the brush.
//
// Memory grows with the surface (six images of N² pixels), not with the volume (a voxel
// grid of the same detail holds N³ cells): docs/property-images.md measures both.
//
// Threads: the haptic loop looks properties up while the viewer paints. Every pixel value is
// read and written through std::atomic_ref with relaxed order, so a lookup never waits and
// never tears a value; a lookup during a stroke may mix old and new pixels for one frame.
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "core/math.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::property_images {

/// What a pixel holds besides its depth, in this order in files.
enum class Channel : std::uint8_t {
  stiffness,            ///< proxy coupling [N/m]
  static_friction,      ///< μs
  kinetic_friction,     ///< μk ≤ μs
  damping,              ///< coupling damping [N·s/m]
  roughness_amplitude,  ///< height of the texture [m]
  roughness_wavelength, ///< its period along the surface [m]
  young_modulus,        ///< E of the material a contact law presses [Pa]; 0: the body's material's
  poisson_ratio,        ///< ν of that material (used with young_modulus)
};
inline constexpr int kChannelCount = 8;
inline constexpr std::array<std::string_view, kChannelCount> kChannelNames = {
    "stiffness",           "static_friction", "kinetic_friction", "damping", "roughness_amplitude",
    "roughness_wavelength", "young_modulus",  "poisson_ratio"};

/// A material, one value per channel.
struct SurfaceProperties {
  std::array<double, kChannelCount> values{};
  [[nodiscard]] double operator[](Channel c) const { return values[static_cast<int>(c)]; }
  double& operator[](Channel c) { return values[static_cast<int>(c)]; }
};
/// Largest values a file or scene may hold: beyond them a number is a typo, not a material.
inline constexpr double kMaxStiffness = 1e6;        ///< N/m
inline constexpr double kMaxFriction = 10.0;
inline constexpr double kMaxDamping = 1e3;          ///< N·s/m
inline constexpr double kMaxRoughnessAmplitude = 0.01;  ///< m
inline constexpr double kMaxRoughnessWavelength = 1.0;  ///< m
inline constexpr double kMaxYoungModulus = 1e12;        ///< Pa (stiffer than diamond is a typo)
inline constexpr double kMaxPoissonRatio = 0.5;
/// Throws InputError at `where` naming the channel when a value is out of range: negative,
/// not finite, beyond the maxima above, μk > μs, or a roughness with no wavelength.
void validate(const SurfaceProperties& properties, const SourceLocation& where);

/// Which channels a paint stroke writes.
using ChannelMask = std::uint8_t;
inline constexpr ChannelMask kAllChannels = (1u << kChannelCount) - 1;
[[nodiscard]] constexpr ChannelMask mask_of(Channel c) { return static_cast<ChannelMask>(1u << static_cast<int>(c)); }

/// One of the six views: it looks along −sign·e_axis from the box face at sign·axis.
struct View {
  int axis = 0;   ///< 0, 1, 2: x, y, z
  int sign = 1;   ///< +1: seen from the high side of the box, −1 from the low side
  int u_axis = 1, v_axis = 2;  ///< the image's columns and rows run along these
  int width = 0, height = 0;
  /// Per pixel, row-major (row v, column u): distance from the face to the first surface
  /// along the ray through the pixel's centre [m]; +inf where the ray meets nothing.
  std::vector<float> depth;
  /// Per pixel, kChannelCount values in Channel order.
  std::vector<float> values;
};

/// The result of a lookup: the material, and which view gave it (−1: no view sees the
/// point within the depth tolerance; the object's base material is returned).
struct Lookup {
  SurfaceProperties properties;
  int view = -1;
};

class PropertyImages {
 public:
  static constexpr int kViewCount = 6;
  /// Pixels along the box's longest side: at most this many (a 4096² image of six floats is
  /// 400 MB per view already).
  static constexpr int kMaxResolution = 4096;

  PropertyImages() = default;
  /// Casts the six images of `surface` (closed and outward oriented: an open surface is an
  /// InputError at `where`) at `resolution` pixels along the box's longest side, every pixel
  /// holding `base`. The box is grown by one pixel on every side, so no surface lies on a face.
  static PropertyImages build(const mesh::TriMesh& surface, int resolution, const SurfaceProperties& base,
                              const SourceLocation& where);
  /// Images read from a file (property_file.hpp): checked for consistency by the reader.
  PropertyImages(const Aabb& box, double pixel, std::uint64_t mesh_hash, const SurfaceProperties& base,
                 std::array<View, kViewCount> views);

  /// The material at surface point `point` with outward `normal` (unit). Allocates nothing;
  /// a few hundred nanoseconds.
  [[nodiscard]] Lookup lookup(const Vec3& point, const Vec3& normal) const;
  /// The texture height at `point` seen by `view` and its gradient in the view's plane
  /// (roughness: amplitude · sin(2πu/λ) · sin(2πv/λ) in the view's pixel axes).
  struct Height {
    double h = 0.0;
    Vec3 gradient = Vec3::Zero();  ///< ∂h/∂x, scene axes (zero along the view's axis)
  };
  [[nodiscard]] Height roughness_height(const Vec3& point, int view, double amplitude, double wavelength) const;

  /// Writes the channels in `mask` of `values` to every pixel whose surface point lies
  /// within `radius` of `center`. Returns how many pixels it wrote. Safe while other
  /// threads look up (not while another thread paints or the images are saved).
  std::size_t paint(const Vec3& center, double radius, const SurfaceProperties& values, ChannelMask mask);

  [[nodiscard]] const Aabb& box() const { return box_; }
  [[nodiscard]] double pixel() const { return pixel_; }
  [[nodiscard]] std::uint64_t mesh_hash() const { return mesh_hash_; }
  [[nodiscard]] const SurfaceProperties& base() const { return base_; }
  [[nodiscard]] const std::array<View, kViewCount>& views() const { return views_; }
  /// Bytes of depth and material data.
  [[nodiscard]] std::size_t bytes() const;
  /// The surface point a pixel's depth gives (scene coordinates); pixel must have a finite depth.
  [[nodiscard]] Vec3 surface_point(int view, int column, int row) const;

 private:
  Aabb box_;
  double pixel_ = 0.0;
  std::uint64_t mesh_hash_ = 0;
  SurfaceProperties base_;
  std::array<View, kViewCount> views_;
};

}  // namespace tactus::property_images
