// `tactus snapshot`: a scene at one instant of a lockstep run, rendered offscreen to PNG.
#include <memory>
#include <string>

#include "app/commands.hpp"
#include "core/input_file.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/png.hpp"
#include "scene/scene.hpp"
#include "viewer/snapshot.hpp"

namespace tactus::app {
namespace {

struct SnapshotFlags {
  std::string scene;
  double at = 0.0;
  std::string output;
  std::string size = "960x720";
  std::string camera;
  bool reveal = false;
  bool wireframe = false;
  bool planes = false;
  bool bvh = false;
  int bvh_levels = 3;
};

scene::Model load_scene(const std::string& path) {
  if (path.empty()) return scene::default_scene();
  return scene::parse_scene(read_input_file(path), path);
}

}  // namespace

Action add_snapshot(CLI::App& app) {
  auto f = std::make_shared<SnapshotFlags>();
  app.add_option("scene", f->scene, "Scene file (TOML); the built-in default scene without one")->check(CLI::ExistingFile);
  app.add_option("--at", f->at, "Time of the run to render [s] (lockstep, reproducible)")->check(CLI::Range(0.0, 3600.0));
  app.add_option("-o,--output", f->output, "PNG file to write")->required();
  app.add_option("--size", f->size, "Image size WIDTHxHEIGHT in pixels (default 960x720)");
  app.add_option("--camera", f->camera, "AZ,EL[,DIST]: camera azimuth and elevation [deg], distance [m]");
  app.add_flag("--reveal", f->reveal, "See-through surfaces showing what lies under them (nodules)");
  app.add_flag("--wireframe", f->wireframe, "Draw the triangle edges");
  app.add_flag("--planes", f->planes, "Draw the contacts' constraint planes");
  app.add_option("--bvh", f->bvh_levels, "Draw the contact BVH's boxes down to this many levels below the root")
      ->check(CLI::Range(0, 12))
      ->each([f](const std::string&) { f->bvh = true; });
  return [f] {
    viewer::SnapshotOptions o;
    o.time = f->at;
    viewer::parse_size(f->size, "--size", o.width, o.height);
    if (!f->camera.empty()) o.camera = viewer::parse_camera(f->camera, "--camera");
    o.view.reveal = f->reveal;
    o.view.wireframe = f->wireframe;
    o.view.show_planes = f->planes;
    o.view.show_bvh = f->bvh;
    o.view.bvh_levels = f->bvh_levels;
    const scene::Model model = load_scene(f->scene);
    const viewer::Snapshot s = viewer::take_snapshot(model, o);
    png::write_rgb(f->output, s.width, s.height, s.rgb);
    log::info("{} at t = {:.3f} s written to {} ({}x{})", model.name, s.frame.t, f->output, s.width, s.height);
    return 0;
  };
}

}  // namespace tactus::app
