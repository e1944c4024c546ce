#include "runtime/vtk_series.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <system_error>

#include <Eigen/LU>

#include "compile/device_setup.hpp"
#include "core/error.hpp"
#include "physics/body.hpp"
#include "physics/fem/constitutive.hpp"
#include "physics/fem/tet_fem.hpp"

namespace tactus::runtime {
namespace {

/// A name as a file name part: letters, digits, '-' and '_' kept, anything else '_'.
std::string file_part(const std::string& name) {
  std::string out;
  for (const char c : name)
    out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
  return out.empty() ? std::string("unnamed") : out;
}

/// XML attribute text.
std::string escaped(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

Mat3 edge_matrix(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  Mat3 m;
  m.col(0) = b - a;
  m.col(1) = c - a;
  m.col(2) = d - a;
  return m;
}

/// von Mises equivalent of a symmetric tensor's deviator: sqrt(k · dev(A):dev(A)).
double deviator_norm(const Mat3& a, double k) {
  const Mat3 dev = a - (a.trace() / 3.0) * Mat3::Identity();
  return std::sqrt(k * dev.cwiseProduct(dev).sum());
}

std::uint64_t bytes_of(const std::filesystem::path& p) {
  std::error_code ec;
  const auto n = std::filesystem::file_size(p, ec);
  return ec ? 0 : static_cast<std::uint64_t>(n);
}

}  // namespace

VtkSeries::VtkSeries(const scene::Model& model, std::filesystem::path dir, double rate,
                     std::vector<const physics::Body*> bodies)
    : dir_(std::move(dir)), scene_stem_(file_part(model.name)), rate_(rate) {
  if (!(rate_ > 0.0) || !std::isfinite(rate_)) throw InputError(fmt::format("--vtk-rate {}: must be above 0", rate_));
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec || !std::filesystem::is_directory(dir_))
    throw InputError(SourceLocation{dir_.string(), {}, {}, {}},
                     "cannot create the folder for the VTK series" + (ec ? ": " + ec.message() : std::string{}));
  pvd_ = dir_ / (scene_stem_ + ".pvd");

  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const scene::Body& sb = model.bodies[b];
    BodyBlock block;
    block.name = sb.name;
    block.stem = scene_stem_ + "_body-" + file_part(sb.name);
    block.body = b;
    if (sb.volume && !sb.volume->tets.empty()) {
      // The volume mesh: its vertices are the simulation's nodes, in order.
      block.nodes_per_cell = 4;
      block.rest = sb.volume->vertices;
      for (std::size_t i = 0; i < block.rest.size(); ++i) block.node_of_point.push_back(static_cast<mesh::Index>(i));
      for (const auto& t : sb.volume->tets) {
        block.cells.insert(block.cells.end(), t.begin(), t.end());
        const Mat3 dm = edge_matrix(block.rest[static_cast<std::size_t>(t[0])], block.rest[static_cast<std::size_t>(t[1])],
                                    block.rest[static_cast<std::size_t>(t[2])], block.rest[static_cast<std::size_t>(t[3])]);
        block.rest_inverse.push_back(dm.inverse());
      }
      const physics::Body* body = b < bodies.size() ? bodies[b] : nullptr;
      if (body)
        if (const auto* fem = dynamic_cast<const physics::TetFem*>(body->model.get());
            fem && fem->elements().size() == sb.volume->tets.size())
          block.fem = fem;
      if (block.fem)
        for (const physics::FemMaterial& m : block.fem->materials()) block.laws.push_back(physics::LawParams::from(m));
    } else {
      // A surface body: its surface vertices are its nodes.
      block.nodes_per_cell = 3;
      block.rest = sb.surface.vertices;
      for (std::size_t i = 0; i < block.rest.size(); ++i) block.node_of_point.push_back(static_cast<mesh::Index>(i));
      for (const auto& t : sb.surface.triangles) block.cells.insert(block.cells.end(), t.begin(), t.end());
    }
    bodies_.push_back(std::move(block));
  }
  for (const scene::Device& d : model.devices)
    tools_.push_back({d.name, scene_stem_ + "_device-" + file_part(d.name), compile::workspace_map(d), {}, false});
  write_pvd();  // fails here, before the run, when the folder cannot be written
}

void VtkSeries::frame(const HapticFrame& f) {
  if (f.device >= tools_.size()) return;
  tools_[f.device].newest = f;
  tools_[f.device].seen = true;
}

void VtkSeries::nodes(const NodeSnapshot& s) {
  // Frame k is due at k / rate; a snapshot at or past it writes it (and skips any it passed).
  const double index = s.t * rate_;
  if (index + 1e-9 < static_cast<double>(next_)) return;
  next_ = static_cast<std::uint64_t>(std::floor(index + 1e-9)) + 1;
  write_frame(s);
}

void VtkSeries::write_frame(const NodeSnapshot& s) {
  const std::size_t k = times_.size();
  for (const BodyBlock& block : bodies_) {
    if (block.body >= s.x.size()) continue;
    const VecX& x = s.x[block.body];
    const VecX& v = s.v[block.body];
    const VecX& contact = s.contact[block.body];
    const std::size_t n = block.rest.size();
    std::vector<Vec3> points(n);
    mesh::VtuFields fields;
    mesh::VtuArray displacement{"displacement", 3, std::vector<double>(3 * n, 0.0)};
    mesh::VtuArray velocity{"velocity", 3, std::vector<double>(3 * n, 0.0)};
    mesh::VtuArray force{"contact_force", 3, std::vector<double>(3 * n, 0.0)};
    for (std::size_t p = 0; p < n; ++p) {
      const auto node = 3 * static_cast<Eigen::Index>(block.node_of_point[p]);
      // A body whose nodes are not the mesh's (none today) stays at rest in the series.
      points[p] = node + 2 < x.size() ? Vec3(x.segment<3>(node)) : block.rest[p];
      for (int c = 0; c < 3; ++c) {
        displacement.values[3 * p + static_cast<std::size_t>(c)] = points[p][c] - block.rest[p][c];
        if (node + 2 < v.size()) velocity.values[3 * p + static_cast<std::size_t>(c)] = v[node + c];
        if (node + 2 < contact.size()) force.values[3 * p + static_cast<std::size_t>(c)] = contact[node + c];
      }
    }
    fields.point_data = {std::move(displacement), std::move(velocity), std::move(force)};
    if (block.nodes_per_cell == 4) {
      const std::size_t m = block.rest_inverse.size();
      mesh::VtuArray strain{"green_strain_von_mises", 1, std::vector<double>(m)};
      mesh::VtuArray ratio{"volume_ratio", 1, std::vector<double>(m)};
      mesh::VtuArray stress{"von_mises_stress", 1, std::vector<double>(m)};
      for (std::size_t e = 0; e < m; ++e) {
        const mesh::Index* t = &block.cells[4 * e];
        const auto at = [&](int a) { return points[static_cast<std::size_t>(t[a])]; };
        const Mat3 F = edge_matrix(at(0), at(1), at(2), at(3)) * block.rest_inverse[e];
        const Mat3 E = 0.5 * (F.transpose() * F - Mat3::Identity());
        strain.values[e] = deviator_norm(E, 2.0 / 3.0);
        const double J = F.determinant();
        ratio.values[e] = J;
        if (block.fem) {
          const auto& el = block.fem->elements()[e];
          const Mat3 P = physics::first_piola_stress(block.laws[static_cast<std::size_t>(el.material)], F);
          const Mat3 sigma = P * F.transpose() / J;  // Cauchy
          stress.values[e] = deviator_norm(0.5 * (sigma + sigma.transpose()), 1.5);
        }
      }
      fields.cell_data = {std::move(strain), std::move(ratio)};
      if (block.fem) fields.cell_data.push_back(std::move(stress));
    }
    const std::filesystem::path file = dir_ / fmt::format("{}_{:06}.vtu", block.stem, k);
    mesh::write_vtu(file, points, block.cells, block.nodes_per_cell, fields);
    bytes_ += bytes_of(file);
  }
  for (const ToolBlock& tool : tools_) {
    // Point 0 the proxy (the contact point), point 1 the device, both in scene coordinates.
    const HapticFrame& f = tool.newest;
    const std::vector<Vec3> points = {f.proxy, tool.map.to_scene(f.position)};
    const Vec3 force = tool.map.rotation * f.force;  // the force on the hand, scene axes
    mesh::VtuFields fields;
    fields.point_data.push_back({"force", 3, {force.x(), force.y(), force.z(), force.x(), force.y(), force.z()}});
    fields.point_data.push_back({"contact", 1, {double(f.contact), double(f.contact)}});
    fields.point_data.push_back({"is_device", 1, {0.0, 1.0}});
    fields.point_data.push_back({"t_frame", 1, {tool.seen ? f.t : 0.0, tool.seen ? f.t : 0.0}});
    const std::filesystem::path file = dir_ / fmt::format("{}_{:06}.vtu", tool.stem, k);
    mesh::write_vtu(file, points, {0, 1}, 1, fields);
    bytes_ += bytes_of(file);
  }
  times_.push_back(s.t);
}

void VtkSeries::close() {
  write_pvd();
  bytes_ += bytes_of(pvd_);
}

void VtkSeries::write_pvd() const {
  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>\n";
  for (std::size_t k = 0; k < times_.size(); ++k) {
    std::size_t part = 0;
    auto entry = [&](const std::string& name, const std::string& stem) {
      out += fmt::format("<DataSet timestep=\"{}\" part=\"{}\" name=\"{}\" file=\"{}_{:06}.vtu\"/>\n", times_[k], part++,
                         escaped(name), escaped(stem), k);
    };
    for (const BodyBlock& b : bodies_) entry(b.name, b.stem);
    for (const ToolBlock& t : tools_) entry(t.name, t.stem);
  }
  out += "</Collection>\n</VTKFile>\n";
  std::ofstream file(pvd_, std::ios::binary | std::ios::trunc);
  if (!file) throw InputError(SourceLocation{pvd_.string(), {}, {}, {}}, "cannot create the file");
  file << out;
  file.close();
  if (!file) throw InputError(SourceLocation{pvd_.string(), {}, {}, {}}, "could not write the file");
}

}  // namespace tactus::runtime
