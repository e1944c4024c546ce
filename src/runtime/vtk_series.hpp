#pragma once
// `tactus run --vtk DIR`: the run as a ParaView time series. Every body is one block (its
// tetrahedra where it has a volume mesh, else its surface triangles) with the nodes'
// displacement, velocity and contact force, the tetrahedra's strain and, for FEM bodies,
// their elastic stress; every device is one block of two points (proxy and device) with
// the force. DIR/NAME.pvd lists one .vtu per block and frame with its time. Fed by the
// recorder, off the haptic threads (docs/outputs.md).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "haptics/device.hpp"
#include "mesh/io/mesh_io.hpp"
#include "physics/fem/material.hpp"
#include "runtime/exchange.hpp"
#include "runtime/recording.hpp"
#include "scene/model.hpp"

namespace tactus::physics {
struct Body;
class TetFem;
}  // namespace tactus::physics

namespace tactus::runtime {

class VtkSeries {
 public:
  /// `bodies[i]`: scene body i as simulated (null: not simulated); FEM bodies give their
  /// stress. Creates `dir` and writes an empty DIR/NAME.pvd, so that a folder that cannot be
  /// written fails before the run (InputError naming it). `rate` [Hz] > 0: frames per
  /// second of simulated time.
  VtkSeries(const scene::Model& model, std::filesystem::path dir, double rate,
            std::vector<const physics::Body*> bodies);

  /// The newest haptic frame of its device (the tool blocks show the newest at each frame).
  void frame(const HapticFrame& f);
  /// Writes a frame of every block when `s` reaches the next multiple of 1 / rate.
  void nodes(const NodeSnapshot& s);
  /// Rewrites the .pvd with every frame written.
  void close();

  [[nodiscard]] std::size_t frames_written() const { return times_.size(); }
  [[nodiscard]] std::uint64_t bytes_written() const { return bytes_; }
  [[nodiscard]] const std::filesystem::path& pvd() const { return pvd_; }

 private:
  struct BodyBlock {
    std::string name;   ///< the body's name
    std::string stem;   ///< file name stem
    std::size_t body = 0;
    int nodes_per_cell = 3;
    std::vector<mesh::Index> cells;
    std::vector<mesh::Index> node_of_point;  ///< simulation node of each point
    std::vector<Vec3> rest;                  ///< per point [m]
    std::vector<Mat3> rest_inverse;          ///< tetrahedra: inverse of the rest edge matrix
    const physics::TetFem* fem = nullptr;    ///< FEM bodies whose elements are these tetrahedra
    std::vector<physics::LawParams> laws;    ///< per material of `fem`
  };
  struct ToolBlock {
    std::string name, stem;
    haptics::WorkspaceMap map;
    HapticFrame newest;
    bool seen = false;
  };
  void write_frame(const NodeSnapshot& s);
  void write_pvd() const;

  std::filesystem::path dir_, pvd_;
  std::string scene_stem_;
  double rate_ = 30.0;
  std::vector<BodyBlock> bodies_;
  std::vector<ToolBlock> tools_;
  std::uint64_t next_ = 0;  ///< the next frame index due (time next_ / rate)
  std::vector<double> times_;
  std::uint64_t bytes_ = 0;
};

}  // namespace tactus::runtime
