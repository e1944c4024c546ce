#include "viewer/view_script.hpp"

// The GL entry points come from viewer/gl.hpp (core profile), not from GLFW's GL header.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

#include "core/error.hpp"

namespace tactus::viewer {
namespace {

double number(const std::string& word, const SourceLocation& where, const char* what) {
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (ec != std::errc() || ptr != word.data() + word.size() || !std::isfinite(value))
    throw InputError(where, fmt::format("{} '{}' is not a number", what, word));
  return value;
}

int button(const std::string& word, const SourceLocation& where) {
  if (word == "left") return GLFW_MOUSE_BUTTON_LEFT;
  if (word == "right") return GLFW_MOUSE_BUTTON_RIGHT;
  if (word == "middle") return GLFW_MOUSE_BUTTON_MIDDLE;
  throw InputError(where, fmt::format("unknown mouse button '{}' (left, right, middle)", word));
}

int modifier(const std::string& word, const SourceLocation& where) {
  if (word == "shift") return GLFW_MOD_SHIFT;
  if (word == "ctrl") return GLFW_MOD_CONTROL;
  throw InputError(where, fmt::format("unknown modifier '{}' (shift, ctrl)", word));
}

int key(const std::string& word, const SourceLocation& where) {
  if (word.size() == 1 && word[0] >= 'a' && word[0] <= 'z') return GLFW_KEY_A + (word[0] - 'a');
  if (word == "escape") return GLFW_KEY_ESCAPE;
  if (word == "space") return GLFW_KEY_SPACE;
  throw InputError(where, fmt::format("unknown key '{}' (a letter a-z, space, escape)", word));
}

}  // namespace

std::vector<ScriptCommand> parse_view_script(const std::string& text, const std::string& source) {
  std::vector<ScriptCommand> out;
  std::istringstream lines(text);
  std::string line;
  for (std::size_t n = 1; std::getline(lines, line); ++n) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream in(line);
    std::vector<std::string> w{std::istream_iterator<std::string>(in), std::istream_iterator<std::string>()};
    if (w.empty()) continue;
    const SourceLocation where{source, n, {}, {}};
    auto want = [&](std::size_t least, std::size_t most, const char* usage) {
      if (w.size() - 1 < least || w.size() - 1 > most) throw InputError(where, fmt::format("expected '{}'", usage));
    };
    ScriptCommand c;
    c.line = n;
    const std::string& op = w[0];
    if (op == "wait") {
      want(1, 1, "wait SECONDS");
      c.op = ScriptOp::wait;
      c.a = number(w[1], where, "seconds");
      if (c.a < 0.0 || c.a > 3600.0) throw InputError(where, "wait: seconds must be in [0, 3600]");
    } else if (op == "frames") {
      want(1, 1, "frames N");
      c.op = ScriptOp::frames;
      c.a = number(w[1], where, "frames");
      if (c.a < 0.0 || c.a > 1e6 || c.a != std::floor(c.a)) throw InputError(where, "frames: N must be a whole number in [0, 1e6]");
    } else if (op == "move") {
      want(2, 2, "move X Y");
      c.op = ScriptOp::move;
      c.a = number(w[1], where, "x");
      c.b = number(w[2], where, "y");
    } else if (op == "press" || op == "release") {
      want(1, op == "press" ? 3 : 1, op == "press" ? "press left|right|middle [shift] [ctrl]" : "release left|right|middle");
      c.op = op == "press" ? ScriptOp::press : ScriptOp::release;
      c.button = button(w[1], where);
      for (std::size_t i = 2; i < w.size(); ++i) c.mods |= modifier(w[i], where);
    } else if (op == "scroll") {
      want(1, 3, "scroll DY [shift] [ctrl]");
      c.op = ScriptOp::scroll;
      c.a = number(w[1], where, "notches");
      for (std::size_t i = 2; i < w.size(); ++i) c.mods |= modifier(w[i], where);
    } else if (op == "key") {
      want(1, 1, "key NAME");
      c.op = ScriptOp::key;
      c.key = key(w[1], where);
    } else if (op == "print") {
      want(0, 0, "print");
      c.op = ScriptOp::print;
    } else if (op == "screenshot") {
      want(1, 1, "screenshot FILE.png");
      c.op = ScriptOp::screenshot;
      c.text = w[1];
    } else if (op == "surface") {
      want(1, 3, "surface STIFFNESS [STATIC_FRICTION KINETIC_FRICTION]");
      c.op = ScriptOp::surface;
      c.a = number(w[1], where, "stiffness");
      c.b = w.size() > 2 ? number(w[2], where, "static friction") : 0.0;
      c.c = w.size() > 3 ? number(w[3], where, "kinetic friction") : 0.0;
    } else if (op == "material") {
      want(2, 3, "material BODY YOUNG_MODULUS [DAMPING]");
      c.op = ScriptOp::material;
      const double body = number(w[1], where, "body index");
      if (body < 0.0 || body != std::floor(body) || body > 1e6) throw InputError(where, "material: BODY is a body index (0, 1, ...)");
      c.button = static_cast<int>(body);
      c.a = number(w[2], where, "Young's modulus");
      c.b = w.size() > 3 ? number(w[3], where, "damping") : -1.0;
    } else if (op == "scene") {
      want(1, 1, "scene FILE.toml");
      c.op = ScriptOp::scene;
      c.text = w[1];
    } else if (op == "quit") {
      want(0, 0, "quit");
      c.op = ScriptOp::quit;
    } else {
      throw InputError(where, fmt::format("unknown command '{}' (wait, frames, move, press, release, scroll, key, "
                                          "print, screenshot, surface, material, scene, quit)", op));
    }
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<ScriptCommand> read_view_script(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(SourceLocation{path.string(), {}, {}, {}}, "cannot open the view script");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return parse_view_script(text, path.string());
}

}  // namespace tactus::viewer
