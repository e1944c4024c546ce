#pragma once
// Synthetic input for the window (`tactus run SCENE --view --view-script FILE`): a text
// file of commands, one a line, fed through the same input handlers as GLFW's callbacks.
// Tests drive the window with it; docs/viewer.md lists the commands.
#include <filesystem>
#include <string>
#include <vector>

namespace tactus::viewer {

enum class ScriptOp {
  wait,        ///< wait SECONDS (wall clock)
  frames,      ///< frames N: let N frames be drawn
  move,        ///< move X Y: cursor to window coordinates (a drag while a button is down)
  press,       ///< press left|right|middle [shift] [ctrl]
  release,     ///< release left|right|middle
  scroll,      ///< scroll DY [shift] [ctrl]: wheel notches, positive away from the user
  key,         ///< key NAME: a shortcut (r, t, w, f, h, escape)
  print,       ///< print: the finger's device position and force to stdout
  screenshot,  ///< screenshot FILE.png: the window's default framebuffer after the next frame
  quit,        ///< quit: close the window
  surface,     ///< surface K MUS MUK: the first device's contact stiffness and friction, live
  material,    ///< material BODY E [ALPHA]: body BODY's (index) Young's modulus [Pa] and damping [1/s], live
  scene,       ///< scene FILE: the scene switcher's choice (ends this run, starts FILE's)
};

struct ScriptCommand {
  ScriptOp op = ScriptOp::wait;
  double a = 0.0, b = 0.0, c = 0.0;  ///< numbers: seconds, frames, x, y, notches, parameters
  int button = 0;           ///< GLFW_MOUSE_BUTTON_* for press / release
  int mods = 0;             ///< GLFW_MOD_* bits
  int key = 0;              ///< GLFW_KEY_* for key
  std::string text;         ///< screenshot path, scene file
  std::size_t line = 0;
};

/// Parses a script; InputError naming file and line for an unknown command or bad argument.
std::vector<ScriptCommand> parse_view_script(const std::string& text, const std::string& source);
std::vector<ScriptCommand> read_view_script(const std::filesystem::path& path);

}  // namespace tactus::viewer
