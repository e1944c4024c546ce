#include "viewer/surface_colours.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

#include <Eigen/Eigenvalues>

namespace tactus::viewer {

RegionColours region_colours(const scene::Model& model, const scene::Body& body) {
  RegionColours out;
  if (!body.volume || body.volume->tet_regions.size() != body.volume->tets.size() ||
      body.surface_to_volume.size() != body.surface.vertices.size())
    return out;
  const auto& tags = body.volume->tet_regions;
  if (std::set<int>(tags.begin(), tags.end()).size() < 2) return out;
  // A region's material: the scene's map, else the body's own.
  const auto material_of = [&](int tag) -> std::string {
    for (const auto& [t, m] : body.region_materials)
      if (t == tag) return model.materials[m].name;
    return body.material ? model.materials[*body.material].name : std::string("region");
  };
  // The boundary face → the tet it bounds (faces by their sorted volume vertices).
  std::map<std::array<mesh::Index, 3>, int> face_region;
  for (std::size_t t = 0; t < body.volume->tets.size(); ++t) {
    const auto& tet = body.volume->tets[t];
    for (int skip = 0; skip < 4; ++skip) {
      std::array<mesh::Index, 3> f{};
      int k = 0;
      for (int i = 0; i < 4; ++i)
        if (i != skip) f[static_cast<std::size_t>(k++)] = tet[static_cast<std::size_t>(i)];
      std::sort(f.begin(), f.end());
      face_region.emplace(f, tags[t]);
    }
  }
  std::vector<std::string> names;  // one colour per material, in order of first sight
  std::map<int, std::size_t> slot;
  std::vector<int> triangle_tag;
  for (const mesh::Triangle& tri : body.surface.triangles) {
    std::array<mesh::Index, 3> f{};
    for (std::size_t i = 0; i < 3; ++i) f[i] = body.surface_to_volume[static_cast<std::size_t>(tri[i])];
    std::sort(f.begin(), f.end());
    const auto found = face_region.find(f);
    const int tag = found == face_region.end() ? tags.front() : found->second;
    triangle_tag.push_back(tag);
    if (!slot.count(tag)) {
      slot[tag] = names.size();
      names.push_back(material_of(tag));
    }
  }
  const std::vector<Colour> colours = body_colours(names);
  for (const int tag : triangle_tag) out.triangles.push_back(colours[slot[tag]]);
  for (const auto& [tag, i] : slot) out.legend.emplace_back(body.name + ": " + names[i], colours[i]);
  return out;
}

double largest_strain(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& a, const Vec3& b, const Vec3& c) {
  // The rest triangle in its own plane: e1 along a0→b0, e2 perpendicular in the plane.
  const Vec3 u0 = b0 - a0, v0 = c0 - a0;
  const double lu = u0.norm();
  const Vec3 n0 = u0.cross(v0);
  if (!(lu > 0.0) || !(n0.norm() > 1e-12 * lu * lu)) return 0.0;
  const Vec3 e1 = u0 / lu, e2 = n0.cross(u0).normalized();
  Eigen::Matrix2d rest;
  rest << u0.dot(e1), v0.dot(e1), u0.dot(e2), v0.dot(e2);
  // F (3×2) maps the rest plane's coordinates to the current edges: [b−a, c−a] = F · rest.
  Eigen::Matrix<double, 3, 2> edges;
  edges.col(0) = b - a;
  edges.col(1) = c - a;
  const Eigen::Matrix<double, 3, 2> f = edges * rest.inverse();
  const Eigen::Matrix2d green = 0.5 * (f.transpose() * f - Eigen::Matrix2d::Identity());
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(green, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
}

void strain_colours(const std::vector<Vec3>& rest, const std::vector<Vec3>& now,
                    const std::vector<mesh::Triangle>& triangles, double full_scale, std::vector<Colour>& out) {
  out.assign(triangles.size(), pressure_colour(0.0));
  if (rest.size() != now.size() || !(full_scale > 0.0)) return;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const auto& t = triangles[i];
    if (std::any_of(t.begin(), t.end(), [&](mesh::Index v) { return v < 0 || static_cast<std::size_t>(v) >= now.size(); }))
      continue;
    const auto p = [&](const std::vector<Vec3>& x, int k) { return x[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])]; };
    const double e = largest_strain(p(rest, 0), p(rest, 1), p(rest, 2), p(now, 0), p(now, 1), p(now, 2));
    out[i] = pressure_colour(std::clamp(e / full_scale, 0.0, 1.0));
  }
}

}  // namespace tactus::viewer
