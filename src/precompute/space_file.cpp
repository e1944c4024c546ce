#include "precompute/space_file.hpp"

#include <fmt/format.h>

#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/hdf5_file.hpp"
#include "precompute/model_identity.hpp"

namespace tactus::precompute {

using hdf5::fail;
using hdf5::Handle;
using hdf5::QuietErrors;
using hdf5::Reader;
using hdf5::Writer;

namespace {

constexpr const char* kFormat = "tactus-configuration-space";
// Version 2 adds the derivatives (points/force_gradient, points/displacement_gradient),
// version 3 the torques (points/torque, points/torque_gradient); older files are still read,
// without them.
constexpr int kVersion = 3;
// The per-point tables are written and read straight from the vectors of Eigen types.
static_assert(sizeof(Vec3) == 3 * sizeof(double) && sizeof(Mat3) == 9 * sizeof(double));

}  // namespace

namespace {

/// One space's attributes and groups under `file` (the file's root, or a level's group).
void write_into(Writer& w, hid_t file, const Space& space) {
  {
    const std::size_t points = space.point_count();
    const auto dofs = static_cast<hsize_t>(space.displacement.rows());
    const auto& s = space.settings;

    w.attribute(file, "format", kFormat);
    w.attribute(file, "version", H5T_NATIVE_INT, &kVersion);
    w.attribute(file, "model_hash", H5T_NATIVE_UINT64, &space.identity.model_hash);
    w.attribute(file, "mesh_hash", H5T_NATIVE_UINT64, &space.identity.mesh_hash);
    const std::uint64_t counts[2] = {space.identity.node_count, space.identity.element_count};
    w.attribute(file, "node_and_element_count", H5T_NATIVE_UINT64, counts, 2);
    const std::uint64_t start = space.start;
    w.attribute(file, "start_point", H5T_NATIVE_UINT64, &start);

    Handle grid(H5Gcreate2(file, "grid", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    w.dataset(grid, "origin", H5T_NATIVE_DOUBLE, {3}, space.grid.origin.data());
    w.dataset(grid, "spacing", H5T_NATIVE_DOUBLE, {1}, &space.grid.spacing);
    w.dataset(grid, "counts", H5T_NATIVE_INT, {3}, space.grid.counts.data());

    Handle settings(H5Gcreate2(file, "settings", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    w.attribute(settings, "body", s.body);
    w.attribute(settings, "interpolation", std::string(to_string(s.interpolation)));
    w.attribute(settings, "contact_node", H5T_NATIVE_INT32, &s.contact_node);
    w.attribute(settings, "patch_radius", H5T_NATIVE_DOUBLE, &s.patch_radius);
    w.attribute(settings, "bounds_min", H5T_NATIVE_DOUBLE, s.bounds_min.data(), 3);
    w.attribute(settings, "bounds_max", H5T_NATIVE_DOUBLE, s.bounds_max.data(), 3);
    w.attribute(settings, "load_steps", H5T_NATIVE_INT, &s.load_steps);
    w.attribute(settings, "max_step_halvings", H5T_NATIVE_INT, &s.max_step_halvings);
    w.attribute(settings, "max_iterations", H5T_NATIVE_INT, &s.max_iterations);
    w.attribute(settings, "tolerance", H5T_NATIVE_DOUBLE, &s.tolerance);
    const int gravity = s.gravity ? 1 : 0;
    w.attribute(settings, "gravity", H5T_NATIVE_INT, &gravity);
    w.attribute(settings, "refine_points", H5T_NATIVE_INT, &s.refine_points);
    if (s.probe.enabled()) {
      w.attribute(settings, "probe_axis", H5T_NATIVE_DOUBLE, s.probe.axis.data(), 3);
      w.attribute(settings, "probe_max_tilt", H5T_NATIVE_DOUBLE, &s.probe.max_tilt);
      w.attribute(settings, "probe_tilt_levels", H5T_NATIVE_INT, &s.probe.tilt_levels);
      w.attribute(settings, "probe_tilt", H5T_NATIVE_DOUBLE, s.tilt.data(), 2);
    }
    if (s.held_node >= 0) {
      w.attribute(settings, "held_node", H5T_NATIVE_INT32, &s.held_node);
      w.attribute(settings, "held_at", H5T_NATIVE_DOUBLE, s.held_at.data(), 3);
    }
    if (s.pair.enabled()) {
      w.attribute(settings, "pair_finger", H5T_NATIVE_INT, &s.finger);
      w.attribute(settings, "pair_node", H5T_NATIVE_INT32, &s.pair.node);
      w.attribute(settings, "pair_bounds_min", H5T_NATIVE_DOUBLE, s.pair.bounds_min.data(), 3);
      w.attribute(settings, "pair_bounds_max", H5T_NATIVE_DOUBLE, s.pair.bounds_max.data(), 3);
    }

    Handle pts(H5Gcreate2(file, "points", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    w.dataset(pts, "status", H5T_NATIVE_UINT8, {points}, space.status.data());
    w.dataset(pts, "source", H5T_NATIVE_INT64, {points}, space.source.data());
    w.dataset(pts, "iterations", H5T_NATIVE_INT32, {points}, space.iterations.data());
    w.dataset(pts, "residual", H5T_NATIVE_DOUBLE, {points}, space.residual.data());
    w.dataset(pts, "seconds", H5T_NATIVE_DOUBLE, {points}, space.seconds.data());
    std::vector<double> force(3 * points);
    for (std::size_t p = 0; p < points; ++p)
      for (std::size_t k = 0; k < 3; ++k) force[3 * p + k] = space.force[p][static_cast<Eigen::Index>(k)];
    w.dataset(pts, "force", H5T_NATIVE_DOUBLE, {points, 3}, force.data());
    w.strings(pts, "reason", space.reason);
    w.dataset(pts, "displacement", H5T_NATIVE_DOUBLE, {points, dofs}, space.displacement.data(), true);
    // [p][k][i]: ∂force_i/∂x_k and ∂displacement_i/∂x_k (the column-major Eigen layouts).
    w.dataset(pts, "force_gradient", H5T_NATIVE_DOUBLE, {points, 3, 3}, space.force_gradient.data());
    w.dataset(pts, "torque", H5T_NATIVE_DOUBLE, {points, 3}, space.torque.data());
    w.dataset(pts, "torque_gradient", H5T_NATIVE_DOUBLE, {points, 3, 3}, space.torque_gradient.data());
    w.dataset(pts, "displacement_gradient", H5T_NATIVE_DOUBLE, {points, 3, dofs}, space.displacement_gradient.data(),
              true);

    // Refined points follow the grid's in every /points dataset; here their places.
    Handle refined(H5Gcreate2(file, "refinement", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    auto places = [](const std::vector<LatticeIndex>& list) {
      std::vector<std::int32_t> flat;
      for (const LatticeIndex& at : list) flat.insert(flat.end(), {at.level, at.ijk[0], at.ijk[1], at.ijk[2]});
      return flat;
    };
    const auto refined_points = places(space.refined_points), refined_cells = places(space.refined_cells);
    w.dataset(refined, "points", H5T_NATIVE_INT32, {space.refined_points.size(), 4}, refined_points.data());
    w.dataset(refined, "cells", H5T_NATIVE_INT32, {space.refined_cells.size(), 4}, refined_cells.data());

    Handle model(H5Gcreate2(file, "model", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    w.dataset(model, "rest_positions", H5T_NATIVE_DOUBLE, {static_cast<hsize_t>(space.rest_positions.size() / 3), 3},
              space.rest_positions.data());
    w.dataset(model, "elements", H5T_NATIVE_INT32, {space.elements.size(), 4}, space.elements.data());
    w.dataset(model, "patch_nodes", H5T_NATIVE_INT32, {s.patch_nodes.size()}, s.patch_nodes.data());
    if (s.held_patch.size() > 1)
      w.dataset(model, "held_patch", H5T_NATIVE_INT32, {s.held_patch.size()}, s.held_patch.data());
    if (s.pair.enabled())
      w.dataset(model, "pair_patch_nodes", H5T_NATIVE_INT32, {s.pair.patch_nodes.size()}, s.pair.patch_nodes.data());
    w.strings(model, "scene", {space.scene_text});
  }
}

void write_file(const std::filesystem::path& path, const std::vector<const Space*>& levels) {
  QuietErrors quiet;
  const std::filesystem::path tmp = path.string() + ".tmp";
  Writer w(path, "the space file");
  {
    Handle file(H5Fcreate(tmp.string().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) fail(path, "cannot create the space file");
    write_into(w, file, *levels.front());
    if (levels.size() > 1) {
      Handle group(H5Gcreate2(file, "levels", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
      for (std::size_t k = 1; k < levels.size(); ++k) {
        Handle level(H5Gcreate2(group, std::to_string(k).c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
        w.check(level.valid(), "level group");
        write_into(w, level, *levels[k]);
      }
    }
    w.check(H5Fflush(file, H5F_SCOPE_GLOBAL) >= 0, "file");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) fail(path, "cannot move the finished space file into place: " + ec.message());
}

/// One space from under `file` (the root, or a level's group).
Space read_from(Reader& r, hid_t file, const std::filesystem::path& path) {
  if (r.text(file, "format") != kFormat) fail(path, "not a Tactus configuration space");
  const int version = r.scalar<int>(file, "version", H5T_NATIVE_INT);
  if (version < 1 || version > kVersion)
    fail(path, fmt::format("space file version {} (this build reads versions 1 to {})", version, kVersion));

  Space space;
  space.identity.model_hash = r.scalar<std::uint64_t>(file, "model_hash", H5T_NATIVE_UINT64);
  space.identity.mesh_hash = r.scalar<std::uint64_t>(file, "mesh_hash", H5T_NATIVE_UINT64);
  std::uint64_t counts[2] = {0, 0};
  r.array(file, "node_and_element_count", H5T_NATIVE_UINT64, counts, 2);
  space.identity.node_count = counts[0];
  space.identity.element_count = counts[1];

  Handle grid(H5Gopen2(file, "grid", H5P_DEFAULT), H5Gclose);
  if (!grid.valid()) fail(path, "missing group 'grid'");
  r.dataset(grid, "origin", H5T_NATIVE_DOUBLE, 3, space.grid.origin.data());
  r.dataset(grid, "spacing", H5T_NATIVE_DOUBLE, 1, &space.grid.spacing);
  r.dataset(grid, "counts", H5T_NATIVE_INT, 3, space.grid.counts.data());
  double total = 1.0;
  for (int c : space.grid.counts) {
    if (c < 1) fail(path, "grid counts must be positive");
    total *= c;
  }
  if (!(space.grid.spacing > 0.0) || total > 1e8 || counts[0] > 100'000'000)
    fail(path, "implausible grid or mesh size");
  space.start = r.scalar<std::uint64_t>(file, "start_point", H5T_NATIVE_UINT64);
  if (space.start >= space.grid.size()) fail(path, "start point outside the grid");

  Handle settings(H5Gopen2(file, "settings", H5P_DEFAULT), H5Gclose);
  if (!settings.valid()) fail(path, "missing group 'settings'");
  auto& s = space.settings;
  s.body = r.text(settings, "body");
  s.interpolation = parse_interpolation(r.text(settings, "interpolation"));
  s.contact_node = r.scalar<std::int32_t>(settings, "contact_node", H5T_NATIVE_INT32);
  s.patch_radius = r.scalar<double>(settings, "patch_radius", H5T_NATIVE_DOUBLE);
  r.array(settings, "bounds_min", H5T_NATIVE_DOUBLE, s.bounds_min.data(), 3);
  r.array(settings, "bounds_max", H5T_NATIVE_DOUBLE, s.bounds_max.data(), 3);
  s.load_steps = r.scalar<int>(settings, "load_steps", H5T_NATIVE_INT);
  s.max_step_halvings = r.scalar<int>(settings, "max_step_halvings", H5T_NATIVE_INT);
  s.max_iterations = r.scalar<int>(settings, "max_iterations", H5T_NATIVE_INT);
  s.tolerance = r.scalar<double>(settings, "tolerance", H5T_NATIVE_DOUBLE);
  s.gravity = r.scalar<int>(settings, "gravity", H5T_NATIVE_INT) != 0;
  if (version >= 2) s.refine_points = r.scalar<int>(settings, "refine_points", H5T_NATIVE_INT);
  if (H5Aexists(settings, "probe_tilt_levels") > 0) {
    r.array(settings, "probe_axis", H5T_NATIVE_DOUBLE, s.probe.axis.data(), 3);
    s.probe.max_tilt = r.scalar<double>(settings, "probe_max_tilt", H5T_NATIVE_DOUBLE);
    s.probe.tilt_levels = r.scalar<int>(settings, "probe_tilt_levels", H5T_NATIVE_INT);
    r.array(settings, "probe_tilt", H5T_NATIVE_DOUBLE, s.tilt.data(), 2);
    if (s.probe.tilt_levels < 3 || s.probe.tilt_levels % 2 == 0 || s.probe.tilt_levels > 99 ||
        !(s.probe.max_tilt > 0.0 && s.probe.max_tilt < 1.6) || !(s.probe.axis.norm() > 0.0) ||
        !s.probe.axis.allFinite() || !s.tilt.allFinite())
      fail(path, "implausible probe settings (leans per axis odd and 3 to 99, largest lean in (0, 90°), an axis)");
  }
  if (H5Aexists(settings, "held_node") > 0) {
    s.held_node = r.scalar<std::int32_t>(settings, "held_node", H5T_NATIVE_INT32);
    r.array(settings, "held_at", H5T_NATIVE_DOUBLE, s.held_at.data(), 3);
    if (s.held_node < 0 || !s.held_at.allFinite()) fail(path, "implausible second interaction point");
  }
  if (H5Aexists(settings, "pair_node") > 0) {
    s.finger = r.scalar<int>(settings, "pair_finger", H5T_NATIVE_INT);
    s.pair.node = r.scalar<std::int32_t>(settings, "pair_node", H5T_NATIVE_INT32);
    r.array(settings, "pair_bounds_min", H5T_NATIVE_DOUBLE, s.pair.bounds_min.data(), 3);
    r.array(settings, "pair_bounds_max", H5T_NATIVE_DOUBLE, s.pair.bounds_max.data(), 3);
    if ((s.finger != 0 && s.finger != 1) || s.pair.node < 0 || !s.pair.bounds_min.allFinite() ||
        !s.pair.bounds_max.allFinite() || s.probe.enabled())
      fail(path, "implausible two-point settings (the point 0 or 1, the other's node and box, no probe)");
  }

  const std::size_t nodes = space.identity.node_count;
  if (total * 12.0 * static_cast<double>(nodes) > 4e9) fail(path, "implausible size of the displacement tables");
  space.allocate(nodes);
  if (version >= 2) {
    Handle refined(H5Gopen2(file, "refinement", H5P_DEFAULT), H5Gclose);
    if (!refined.valid()) fail(path, "missing group 'refinement'");
    auto places = [&](const char* name) {
      const auto dims = r.dims(refined, name, 2);
      if (dims[1] != 4 || dims[0] > 10'000'000) fail(path, fmt::format("refinement/{} is not a list of places", name));
      std::vector<std::int32_t> flat(4 * dims[0]);
      r.dataset(refined, name, H5T_NATIVE_INT32, flat.size(), flat.data());
      std::vector<LatticeIndex> list;
      for (std::size_t i = 0; i < dims[0]; ++i) {
        const LatticeIndex at{flat[4 * i], {flat[4 * i + 1], flat[4 * i + 2], flat[4 * i + 3]}};
        if (at.level < 0 || at.level > Space::kMaxLevel || !Space::fits(at))
          fail(path, fmt::format("refinement/{} entry {} is not a lattice place", name, i));
        list.push_back(at);
      }
      return list;
    };
    for (const LatticeIndex& at : places("points")) {
      if (at.level < 1 || space.find(at)) fail(path, "refinement/points repeats a point or names a grid point");
      space.add_point(at);
    }
    for (const LatticeIndex& cell : places("cells")) {
      if (cell.level >= Space::kMaxLevel) fail(path, "refinement/cells splits a cell of the finest level");
      space.refine_cell(cell);
    }
  }
  const std::size_t points = space.point_count();
  Handle pts(H5Gopen2(file, "points", H5P_DEFAULT), H5Gclose);
  if (!pts.valid()) fail(path, "missing group 'points'");
  std::vector<std::uint8_t> status(points);
  r.dataset(pts, "status", H5T_NATIVE_UINT8, points, status.data());
  for (std::size_t p = 0; p < points; ++p) {
    if (status[p] > 3) fail(path, fmt::format("point {} has an unknown status {}", p, status[p]));
    space.status[p] = static_cast<PointStatus>(status[p]);
  }
  r.dataset(pts, "source", H5T_NATIVE_INT64, points, space.source.data());
  r.dataset(pts, "iterations", H5T_NATIVE_INT32, points, space.iterations.data());
  r.dataset(pts, "residual", H5T_NATIVE_DOUBLE, points, space.residual.data());
  r.dataset(pts, "seconds", H5T_NATIVE_DOUBLE, points, space.seconds.data());
  std::vector<double> force(3 * points);
  r.dataset(pts, "force", H5T_NATIVE_DOUBLE, 3 * points, force.data());
  for (std::size_t p = 0; p < points; ++p) space.force[p] = Vec3(force[3 * p], force[3 * p + 1], force[3 * p + 2]);
  space.reason = r.strings(pts, "reason", points);
  r.dataset(pts, "displacement", H5T_NATIVE_DOUBLE, points * 3 * nodes, space.displacement.data());
  space.has_gradients = version >= 2;
  if (space.has_gradients) {
    r.dataset(pts, "force_gradient", H5T_NATIVE_DOUBLE, points * 9, space.force_gradient.data());
    r.dataset(pts, "displacement_gradient", H5T_NATIVE_DOUBLE, points * 9 * nodes, space.displacement_gradient.data());
  }
  space.has_torques = version >= 3;
  if (space.has_torques) {
    r.dataset(pts, "torque", H5T_NATIVE_DOUBLE, points * 3, space.torque.data());
    r.dataset(pts, "torque_gradient", H5T_NATIVE_DOUBLE, points * 9, space.torque_gradient.data());
  }

  Handle model(H5Gopen2(file, "model", H5P_DEFAULT), H5Gclose);
  if (!model.valid()) fail(path, "missing group 'model'");
  space.rest_positions.resize(static_cast<Eigen::Index>(3 * nodes));
  r.dataset(model, "rest_positions", H5T_NATIVE_DOUBLE, 3 * nodes, space.rest_positions.data());
  const auto elements = r.dims(model, "elements", 2);
  if (elements[1] != 4 || elements[0] > 1'000'000'000) fail(path, "dataset 'elements' is not a list of tetrahedra");
  space.elements.resize(elements[0]);
  r.dataset(model, "elements", H5T_NATIVE_INT32, 4 * space.elements.size(), space.elements.data());
  const auto patch = r.dims(model, "patch_nodes", 1);
  if (patch[0] > nodes) fail(path, "more patch nodes than nodes");
  s.patch_nodes.resize(patch[0]);
  r.dataset(model, "patch_nodes", H5T_NATIVE_INT32, s.patch_nodes.size(), s.patch_nodes.data());
  auto node_list = [&](const char* name, std::vector<std::int32_t>& list) {
    const auto n = r.dims(model, name, 1);
    if (n[0] > nodes) fail(path, fmt::format("more nodes in model/{} than in the mesh", name));
    list.resize(n[0]);
    r.dataset(model, name, H5T_NATIVE_INT32, list.size(), list.data());
    for (auto v : list)
      if (v < 0 || static_cast<std::size_t>(v) >= nodes) fail(path, fmt::format("model/{} names node {}", name, v));
  };
  if (s.held_node >= 0 && H5Lexists(model, "held_patch", H5P_DEFAULT) > 0) node_list("held_patch", s.held_patch);
  if (s.pair.enabled()) node_list("pair_patch_nodes", s.pair.patch_nodes);
  space.scene_text = r.strings(model, "scene", 1).front();
  return space;
}

}  // namespace

void write_space(const std::filesystem::path& path, const Space& space) { write_file(path, {&space}); }

void write_space_levels(const std::filesystem::path& path, const std::vector<Space>& levels) {
  if (levels.empty()) throw InputError("a space has at least one level");
  std::vector<const Space*> list;
  for (const Space& level : levels) list.push_back(&level);
  write_file(path, list);
}

std::vector<Space> read_space_levels(const std::filesystem::path& path) {
  QuietErrors quiet;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail(path, "file not found");
  if (H5Fis_hdf5(path.string().c_str()) <= 0) fail(path, "not an HDF5 file");
  Handle file(H5Fopen(path.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.valid()) fail(path, "cannot open the HDF5 file");
  Reader r(path);
  std::vector<Space> levels;
  levels.push_back(read_from(r, file, path));
  const SpaceSettings first = levels.front().settings;  // a copy: levels grows
  if (!first.probe.enabled() && !first.pair.enabled()) return levels;
  Handle group(H5Gopen2(file, "levels", H5P_DEFAULT), H5Gclose);
  if (!group.valid()) fail(path, "a space of several levels without its group 'levels'");
  // A probe space has a level per lean; a two-point space 2 + nA + nB, nB being the size of
  // level 1's grid (precompute/pair.hpp).
  std::size_t count = first.pair.enabled() ? 2 : first.probe.level_count();
  for (std::size_t k = 1; k < count; ++k) {
    Handle level(H5Gopen2(group, std::to_string(k).c_str(), H5P_DEFAULT), H5Gclose);
    if (!level.valid()) fail(path, fmt::format("level {} of {} is missing", k, count));
    levels.push_back(read_from(r, level, path));
    if (levels.back().identity.mesh_hash != levels.front().identity.mesh_hash)
      fail(path, fmt::format("level {} was built for another mesh than level 0", k));
    if (first.pair.enabled() && k == 1) count = 2 + levels[0].grid.size() + levels[1].grid.size();
  }
  return levels;
}

Space read_space(const std::filesystem::path& path) { return std::move(read_space_levels(path).front()); }

Space load_space(const std::filesystem::path& path, const ModelIdentity& model) {
  Space space = read_space(path);
  check_identity(space.identity, model, path.string());
  return space;
}

}  // namespace tactus::precompute
