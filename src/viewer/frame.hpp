#pragma once
// What the renderer draws: a plain description of one visual frame, built from a run's
// published snapshots (visual_feed.hpp) or by hand (tests). Scene units [m, N, Pa].
#include <string>
#include <utility>
#include <vector>

#include "core/math.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::viewer {

/// Linear RGB in [0, 1].
using Colour = Vec3;

/// A body's deformed surface.
struct SurfaceView {
  std::string name;
  std::vector<Vec3> positions;
  std::vector<mesh::Triangle> triangles;
  Colour colour = Colour(0.9, 0.72, 0.62);
  /// A colour per triangle instead of `colour` (a body's regions, a fabric's strain); empty:
  /// `colour` everywhere.
  std::vector<Colour> triangle_colours;
  /// What the legend lists for this surface instead of its name and colour (its regions).
  std::vector<std::pair<std::string, Colour>> legend;
  /// Contact pressure per vertex [Pa]; empty = no contact on this surface.
  std::vector<double> pressure;
  /// Drawn see-through when the view asks for transparency (it then reveals what lies under).
  bool translucent_when_revealing = true;
  /// Drawn behind any surface it coincides with: a body whose embedded layers lie on its
  /// boundary (a skin sheet on a tissue block's top) would otherwise fight them pixel by pixel.
  bool recessed = false;
  /// Non-null: these positions and triangles are the same every frame this id is given (a
  /// rigid object's impostor level), so the renderer keeps their vertices (and, where it
  /// can, on the GPU) instead of rebuilding and sending them each frame.
  const void* static_id = nullptr;
};

/// A sphere: a tool's contact sphere, its device position, a nodule under the skin.
struct SphereView {
  Vec3 centre = Vec3::Zero();
  double radius = 0.0;
  Colour colour = Colour(0.4, 0.6, 0.95);
  double opacity = 1.0;
  /// Hidden under the surface: drawn only when the view reveals subsurface structures.
  bool subsurface = false;
};

/// A force vector drawn as an arrow from `origin`, `length_per_newton` metres per newton up
/// to `max_length` (a spike must not become a pole across the scene), its value written at
/// its tip.
struct ArrowView {
  Vec3 origin = Vec3::Zero();
  Vec3 force = Vec3::Zero();  ///< [N]
  double length_per_newton = 0.01;
  double max_length = 0.05;  ///< [m]
  Colour colour = Colour(0.95, 0.85, 0.1);
  std::string label;  ///< e.g. "hand 1.23 N"; empty = none
  /// The drawn length [m].
  [[nodiscard]] double length() const;
};

/// A needle: shaft, bevelled tip and hub.
struct NeedleView {
  Vec3 tip = Vec3::Zero();
  Vec3 axis = -Vec3::UnitZ();  ///< unit, from the hub towards the tip
  double length = 0.08;        ///< [m]
  double radius = 0.0005;      ///< [m] (drawn at least a few pixels wide)
  Colour colour = Colour(0.78, 0.8, 0.84);
};

/// A line of text in a corner of the view (a device's force, a needle's depth and layers).
struct StatusLine {
  std::string text;
  Colour colour = Colour(0.95, 0.95, 0.95);
};

/// A translucent square in a plane (a contact's constraint plane).
struct QuadView {
  Vec3 centre = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
  double half = 0.01;  ///< from the centre to a side [m]
  Colour colour = Colour(0.3, 0.9, 0.5);
  double opacity = 0.4;
};

/// The edges of an axis-aligned box (a node of a bounding volume hierarchy).
struct BoxView {
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  Colour colour = Colour(0.9, 0.5, 0.9);
};

struct FrameView {
  double t = 0.0;  ///< [s] simulated time of the surfaces
  std::vector<SurfaceView> surfaces;
  std::vector<SphereView> spheres;
  std::vector<ArrowView> arrows;
  std::vector<QuadView> quads;  ///< debug view: constraint planes
  std::vector<BoxView> boxes;   ///< debug view: BVH nodes
  std::vector<NeedleView> needles;
  std::vector<StatusLine> status;  ///< one per device
  /// Pressure shown at the top of the false-colour scale [Pa].
  double pressure_full_scale = 2.0e4;
};

/// Display switches of the view.
struct ViewOptions {
  bool reveal = false;     ///< translucent surfaces; subsurface structures shown
  bool wireframe = false;  ///< triangle edges over the shading
  bool shadows = true;
  bool floor = true;  ///< the floor under the scene that receives its shadows
  /// Shadow edges filtered over 3 × 3 taps; one tap where every pixel's shading costs CPU
  /// (a software renderer).
  bool soft_shadows = true;
  bool show_pressure = true;
  bool show_forces = true;
  bool show_planes = false;  ///< the contact's constraint plane under each touching tool
  bool show_bvh = false;     ///< the top levels of each surface's contact BVH
  int bvh_levels = 3;        ///< levels below the root drawn by show_bvh
  bool show_levels = false;  ///< touchable objects at their haptic impostor level, coloured by it
  bool graphics_levels = true;  ///< touchable objects drawn at graphics impostors chosen per frame
};

/// Axis-aligned bounds of everything in the frame (surfaces and spheres).
Aabb frame_bounds(const FrameView& frame);

/// False-colour ramp for a value in [0, 1]: blue, cyan, green, yellow, red.
Colour pressure_colour(double fraction);

/// A body's colour from what its name says it is (skin, fat, muscle, fascia, ligament,
/// artery, vein, nerve, bone, liver...), else from a palette by `index`. The legend, the
/// window and the snapshots use it, so a layer has one colour everywhere.
Colour body_colour(const std::string& name, std::size_t index);
/// body_colour for each name, a repeated colour darkened a step each time (two fasciae,
/// two bones), so that the legend tells every body apart.
std::vector<Colour> body_colours(const std::vector<std::string>& names);

}  // namespace tactus::viewer
