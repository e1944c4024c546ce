#pragma once
// Needle insertion through layered tissue (seed 003 §3.5 and §4): the needle is a line
// segment ending at its tip, and each layer it meets goes through three stages:
//   untouched → deforming (a stiff spring holds the tip at the surface where it touched,
//   and the tissue dents under the reaction) → ruptured (the spring force reached the
//   layer's threshold: the resistance drops, and from then on the shaft feels viscous and
//   Coulomb friction per length inside the layer, plus a lateral spring towards the
//   puncture path that stiffens with depth).
// Pure and allocation-free per frame: the interaction loop finds where the needle line
// crosses each layer's surface (NeedleSurfaces), and update() turns that, the tip and its
// velocity into the force on the hand and the load on the tissue.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/math.hpp"

namespace tactus::haptics {

inline constexpr std::size_t kMaxNeedleLayers = 8;
/// Ruptures kept for the report (several insertions at new sites each tear every layer).
inline constexpr std::size_t kMaxNeedleRuptures = 4 * kMaxNeedleLayers;

/// One tissue layer the needle may pierce (a body's surface).
struct NeedleLayer {
  std::size_t body = 0;            ///< the body whose surface bounds the layer
  double rupture_force = 2.0;      ///< spring force at which the layer tears [N]
  double stiffness = 1000.0;       ///< resistance of the surface before rupture [N/m]
  double viscous_friction = 100.0; ///< shaft friction per speed and per length inside [N·s/m²]
  double coulomb_friction = 50.0;  ///< shaft friction per length inside [N/m]
};

struct NeedleConfig {
  double length = 0.08;              ///< shaft length: the most of it that can be inside [m]
  /// Stiffness of the spring towards the puncture path with the whole shaft inside; it
  /// grows linearly with the inserted depth from zero at the first puncture [N/m].
  double lateral_stiffness = 200.0;
  /// Coulomb friction is smoothed below this axial speed, so it does not chatter at rest [m/s].
  double stick_speed = 1e-3;
  /// How far past a surface the tip may already be when it engages a layer and still have
  /// the spring start at the surface (farther, it starts at the tip: no force step) [m].
  double engage_slack = 5e-4;
  /// Withdrawn from every hole and moved this far off the puncture path, the needle is at a
  /// new site: the next insertion tears the layers anew (closer, it finds its old holes) [m].
  double new_site_distance = 3e-3;
  std::vector<NeedleLayer> layers;  ///< at most kMaxNeedleLayers
  /// The planned path (entry → target) that the lateral deviation is measured against;
  /// absent: the path through the first puncture along the needle's axis then.
  std::optional<std::array<Vec3, 2>> planned;
};

/// Where the needle's line crosses one layer's surface, newest interaction result.
struct NeedleLayerSurface {
  bool entry_found = false;
  Vec3 entry = Vec3::Zero();             ///< first entering crossing along the axis [m]
  std::int32_t entry_triangle = -1;      ///< surface triangle of `entry`
  Vec3 entry_barycentric = Vec3::Zero();
  Vec3 entry_normal = Vec3::Zero();      ///< unit face normal of `entry_triangle`
  bool exit_found = false;
  Vec3 exit = Vec3::Zero();              ///< first leaving crossing after the entry [m]
};

/// Per layer of the config, in the same order.
struct NeedleSurfaces {
  std::array<NeedleLayerSurface, kMaxNeedleLayers> layers{};
};

enum class NeedleStage : std::uint8_t { untouched, deforming, ruptured };

struct NeedleRupture {
  std::size_t layer = 0;  ///< index into NeedleConfig::layers
  double t = 0.0;         ///< [s]
  double force = 0.0;     ///< spring force when the layer tore [N]
  Vec3 point = Vec3::Zero();  ///< where the hole starts [m]
};

struct NeedleOutput {
  Vec3 force = Vec3::Zero();  ///< on the hand [N]
  bool touching = false;      ///< a layer resists or the shaft is inside tissue
  /// The layer whose surface carries the reaction (the deforming one, else the deepest
  /// ruptured one the shaft is in); −1: none.
  int load_layer = -1;
  std::int32_t load_triangle = -1;
  Vec3 load_barycentric = Vec3::Zero();
  Vec3 load_point = Vec3::Zero();
  /// A layer tore this frame.
  std::optional<NeedleRupture> rupture;
  double spring_force = 0.0;   ///< of the deforming layer [N]
  double axial_friction = 0.0; ///< signed along the axis, on the hand [N]
  double lateral_deviation = 0.0;  ///< tip from the planned (or puncture) path [m]
  /// The lateral spring's part of `force` (on the hand) [N]. Its reaction acts on the tissue
  /// along the shaft inside it, from `shaft_from` (the first puncture) to the tip: the shaft
  /// pushes the tissue it passes through, so a lateral move of the needle moves the tissue.
  Vec3 lateral_force = Vec3::Zero();
  bool shaft = false;  ///< the shaft is inside tissue past a puncture
  Vec3 shaft_from = Vec3::Zero();
};

class NeedleInsertion {
 public:
  /// Throws std::invalid_argument for more than kMaxNeedleLayers layers or a non-positive
  /// length, stiffness or threshold (the scene loader reports these with their location).
  explicit NeedleInsertion(NeedleConfig config);

  /// One frame: `tip` and unit `axis` (towards the tip) in scene coordinates, the tip's
  /// velocity, the newest surface crossings, and the time (for the rupture record).
  NeedleOutput update(const Vec3& tip, const Vec3& axis, const Vec3& velocity, const NeedleSurfaces& surfaces,
                      double t);

  [[nodiscard]] const NeedleConfig& config() const { return config_; }
  [[nodiscard]] NeedleStage stage(std::size_t layer) const { return layers_[layer].stage; }
  [[nodiscard]] std::span<const NeedleRupture> ruptures() const { return {ruptures_.data(), rupture_count_}; }
  /// Whether the tip has ever pressed on a layer.
  [[nodiscard]] bool touched() const { return touched_; }
  /// Largest lateral deviation of the tip from the planned path while inside tissue [m].
  [[nodiscard]] double max_deviation() const { return max_deviation_; }
  /// The deviation at the last frame the tip was inside tissue [m].
  [[nodiscard]] double last_deviation() const { return last_deviation_; }

 private:
  struct LayerState {
    NeedleStage stage = NeedleStage::untouched;
    Vec3 anchor = Vec3::Zero();  ///< deforming: where the spring holds the tip; ruptured: the hole
    std::int32_t triangle = -1;  ///< surface triangle of the touch point
    Vec3 barycentric = Vec3::Zero();
  };
  void engage(const Vec3& tip, const Vec3& axis, const NeedleSurfaces& surfaces);
  /// Out of every hole and away from the puncture path: forget the holes (a new site).
  void leave_site_if_moved(const Vec3& tip, const Vec3& axis);

  NeedleConfig config_;
  std::array<LayerState, kMaxNeedleLayers> layers_{};
  int deforming_ = -1;
  std::array<NeedleRupture, kMaxNeedleRuptures> ruptures_{};
  std::size_t rupture_count_ = 0;
  bool punctured_ = false;
  bool touched_ = false;
  Vec3 path_point_ = Vec3::Zero(), path_axis_ = Vec3::UnitZ();  ///< the puncture path
  Vec3 planned_axis_ = Vec3::UnitZ();
  double max_deviation_ = 0.0, last_deviation_ = 0.0;
};

}  // namespace tactus::haptics
