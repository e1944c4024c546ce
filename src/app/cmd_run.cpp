#include <cstdio>
#include <string>

#include "app/commands.hpp"
#include "core/log.hpp"
#include "scene/scene.hpp"

namespace tactus::app {

Action add_run(CLI::App& app) {
  auto scene_path = std::make_shared<std::string>();
  app.add_option("scene", *scene_path, "Scene file (TOML); the built-in default scene without one")
      ->check(CLI::ExistingFile);
  return [scene_path] {
    const scene::Model model =
        scene_path->empty() ? scene::default_scene() : scene::load_scene(*scene_path);
    std::fputs(scene::summarize(model).c_str(), stdout);
    log::info("scene loaded and validated; the simulation loops are not part of this build yet");
    return 0;
  };
}

}  // namespace tactus::app
