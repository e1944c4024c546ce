#pragma once
// The window's debug views, built on the viewer's thread from what the run publishes (the
// surface snapshots and the haptic frames), never from the loops' own structures:
//  - the contact's constraint plane: the tangent plane of the touched surface at the
//    contact point, as a translucent square with its normal;
//  - the top levels of each surface's contact BVH: the tree the interaction loop builds
//    (contact::TriangleBvh over the body's surface at rest), refitted here to the
//    published surface.
#include <vector>

#include "contact/bvh.hpp"
#include "scene/model.hpp"
#include "viewer/frame.hpp"
#include "viewer/visual_feed.hpp"

namespace tactus::viewer {

class DebugViews {
 public:
  explicit DebugViews(const scene::Model& model) : model_(model) {}

  /// Adds the views `view` asks for to `frame` (whose surfaces are the published ones).
  void add(const std::vector<ToolView>& tools, const ViewOptions& view, FrameView& frame);

 private:
  const scene::Model& model_;
  std::vector<contact::TriangleBvh> trees_;  ///< per body, built on first use
  std::vector<std::pair<Vec3, Vec3>> boxes_;
};

/// The unit normal of the surface at `point`: the area-weighted normal at the surface
/// vertex nearest to it, over every surface of the frame; zero when there is none.
Vec3 surface_normal_near(const FrameView& frame, const Vec3& point);

}  // namespace tactus::viewer
