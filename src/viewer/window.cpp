#include "viewer/window.hpp"

// The GL entry points come from viewer/gl.hpp (core profile), not from GLFW's GL header.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <fmt/format.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <numbers>
#include <optional>
#include <thread>
#include <utility>
#include <variant>

#include "core/error.hpp"
#include "core/png.hpp"
#include "compile/device_setup.hpp"
#include "runtime/devices.hpp"
#include "runtime/live_parameters.hpp"
#include "viewer/debug_views.hpp"
#include "viewer/frame_budget.hpp"
#include "viewer/camera.hpp"
#include "viewer/mouse_device.hpp"
#include "viewer/overlay.hpp"
#include "viewer/panel.hpp"
#include "viewer/gl.hpp"
#include "viewer/renderer.hpp"
#include "viewer/scene_target.hpp"
#include "viewer/touchables_view.hpp"
#include "viewer/view_script.hpp"
#include "viewer/visual_feed.hpp"

namespace tactus::viewer {
namespace {

/// The overlay through Dear ImGui, under the panel; `scale`: window units per pixel.
void paint_with_imgui(const Overlay& overlay, float scale) {
  ImDrawList* list = ImGui::GetBackgroundDrawList();
  const auto colour = [](const Colour& c, double alpha) {
    return ImGui::ColorConvertFloat4ToU32(
        ImVec4(static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z()), static_cast<float>(alpha)));
  };
  for (const OverlayRect& r : overlay.rects)
    list->AddRectFilled(ImVec2(scale * r.x0, scale * r.y0), ImVec2(scale * r.x1, scale * r.y1), colour(r.colour, 1.0));
  for (const OverlayText& t : overlay.texts) {
    float x = scale * t.x;
    if (t.right_aligned) x -= ImGui::CalcTextSize(t.text.c_str()).x;
    list->AddText(ImVec2(x + 1, scale * t.y + 1), IM_COL32(0, 0, 0, 255), t.text.c_str());
    list->AddText(ImVec2(x, scale * t.y), colour(t.colour, 1.0), t.text.c_str());
  }
}

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// GLFW reports errors through a callback; the window's thread keeps the last one for the
// message when a window cannot be opened.
std::string g_glfw_error;
extern "C" void on_glfw_error(int /*code*/, const char* description) { g_glfw_error = description ? description : ""; }

/// GLFW for the whole process: initialised by the first window, terminated at exit. A scene
/// switch thus keeps the display connection: an X server left without clients resets, and
/// Xvfb (as xvfb-run starts it) refuses the next window while it does.
bool glfw_ready() {
  static const bool ready = [] {
    if (!glfwInit()) return false;
    std::atexit(glfwTerminate);
    return true;
  }();
  return ready;
}

constexpr double kOrbitDegreesPerPixel = 0.3;
constexpr double kZoomPerNotch = 0.9;

/// GLFW, the window, its context, Dear ImGui and the renderer, torn down in reverse order.
class Window {
 public:
  Window(const scene::Model& model, const WindowOptions& options, VisualFeed& feed, MouseChannel* mouse,
         const haptics::WorkspaceMap& map, std::string mouse_device, std::string recording,
         runtime::LiveParameters& live, const compile::Touchables& touchables)
      : model_(model), options_(options), feed_(feed), mouse_(mouse), map_(map),
        mouse_device_(std::move(mouse_device)), recording_(std::move(recording)), live_(live), debug_(model),
        touchables_(touchables) {
    for (const scene::Body& b : model.bodies) body_names_.push_back(b.name);
    for (const scene::Device& d : model.devices) device_names_.push_back(d.name);
    scenes_ = options.scenes;
    // A bad script is reported before anything opens or runs.
    if (options.script) script_ = read_view_script(*options.script);
    glfwSetErrorCallback(on_glfw_error);
    if (!glfw_ready())
      throw InputError(fmt::format("--view: no display to open a window on ({}); set DISPLAY, or run under "
                                   "xvfb-run; 'tactus snapshot' renders without one",
                                   g_glfw_error.empty() ? "GLFW does not initialize" : g_glfw_error));
    glfwDefaultWindowHints();  // a previous scene's window may have changed them
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    open_window(4);
    // A software renderer shades every sample on the CPU: there the window has one sample a
    // pixel and the shadows one tap (docs/viewer.md, "The frame budget").
    const auto* renderer_name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    renderer_name_ = renderer_name ? renderer_name : "";
    software_ = is_software_renderer(renderer_name_);
    if (software_) {
      glfwDestroyWindow(window_);
      window_ = nullptr;
      open_window(0);
      view_.soft_shadows = false;
    }
    // The scaled scene is stretched over the window by a blit, which a multisampled window
    // cannot take (GL 3.3): there (a GPU's window) the scene stays at full size.
    GLint samples = 0;
    glGetIntegerv(GL_SAMPLES, &samples);
    if (options.frame_budget_ms > 0.0 && samples == 0) {
      ResolutionGovernor::Settings budget;
      budget.budget_ms = options.frame_budget_ms;
      governor_.emplace(budget);
    }
    glfwSwapInterval(0);  // the loop paces itself (WindowOptions::max_fps)
    glfwSetWindowUserPointer(window_, this);
    glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double x, double y) { self(w).on_cursor(x, y); });
    glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int b, int action, int mods) {
      self(w).on_button(b, action, mods, false);
    });
    glfwSetScrollCallback(window_, [](GLFWwindow* w, double /*dx*/, double dy) {
      self(w).on_scroll(dy, self(w).modifiers(), false);
    });
    glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int /*scancode*/, int action, int mods) {
      self(w).on_key(key, action, mods, false);
    });
    // A software renderer fills the shadow map on the CPU: a quarter of the texels there.
    renderer_ = std::make_unique<Renderer>(software_ ? 1024 : 2048);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working directory
    ImGui::StyleColorsDark();
    // Installed after ours: ImGui's callbacks see each event first, then call ours.
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 330 core");
    imgui_ = true;

    if (touchables_.any())
      level_cost_ = options.frame_budget_ms > 0.0 ? measure_level_draw_times(touchables_, view_) : level_triangles(touchables_);
    const FrameView rest = feed_.build();
    scene_box_ = frame_bounds(rest);
    home_camera_ = OrbitCamera::framing(scene_box_);
    camera_ = home_camera_;
    const std::vector<ToolView> tools = feed_.tools();
    finger_radius_ = tools.empty() ? 0.0 : tools.front().radius;
    // Above the middle of the scene, the finger's lowest point 1/2 radius over the top.
    const Vec3 centre = 0.5 * (scene_box_.min + scene_box_.max);
    home_finger_ = Vec3(centre.x(), centre.y(), scene_box_.max.z() + 1.5 * finger_radius_);
    finger_ = home_finger_;
  }

  ~Window() {
    if (imgui_) {
      ImGui_ImplOpenGL3_Shutdown();
      ImGui_ImplGlfw_Shutdown();
      ImGui::DestroyContext();
    }
    renderer_.reset();  // needs the context
    scene_target_.release();
    if (window_) glfwDestroyWindow(window_);
  }
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  /// The scene chosen in the switcher, to run after this one; empty = none.
  [[nodiscard]] const std::string& next_scene() const { return next_scene_; }

  /// Where the mouse device starts, device coordinates.
  [[nodiscard]] Vec3 home_device_position() const { return map_.to_device(home_finger_); }

  /// Draws until the window is closed, `stop` is set, the time is up or `run_over` is set.
  void loop(std::atomic<bool>& stop, const std::atomic<bool>& run_over, WindowReport& report) {
    const Clock::time_point start = Clock::now();
    Clock::time_point rate_window = start;
    std::uint64_t rate_frames = 0;
    std::vector<double> frame_ms, scales;
    const auto period = std::chrono::duration<double>(1.0 / std::max(options_.max_fps, 1.0));
    while (!stop.load() && !run_over.load(std::memory_order_acquire) && !glfwWindowShouldClose(window_) && !quit_) {
      if (options_.seconds > 0.0 && seconds_since(start) >= options_.seconds) break;
      const Clock::time_point frame_start = Clock::now();
      glfwPollEvents();
      run_script();
      if (mouse_) mouse_->set(map_.to_device(finger_));
      draw_frame();
      frame_ms.push_back(seconds_since(frame_start) * 1e3);
      scales.push_back(scale_);
      last_frame_ms_ = frame_ms.back();
      if (governor_) governor_->add(last_frame_ms_);
      ++report.frames;
      ++rate_frames;
      if (const double window = seconds_since(rate_window); window >= 0.5) {
        visual_rate_ = static_cast<double>(rate_frames) / window;
        rate_frames = 0;
        rate_window = Clock::now();
      }
      std::this_thread::sleep_until(frame_start + std::chrono::duration_cast<Clock::duration>(period));
    }
    stop.store(true);  // ends the run when the window closed first
    report.seconds = seconds_since(start);
    report.rate = report.seconds > 0.0 ? static_cast<double>(report.frames) / report.seconds : 0.0;
    if (!frame_ms.empty()) {
      std::sort(frame_ms.begin(), frame_ms.end());
      const auto at = [&](double q) { return frame_ms[static_cast<std::size_t>(q * static_cast<double>(frame_ms.size() - 1))]; };
      report.frame_p50_ms = at(0.5);
      report.frame_p99_ms = at(0.99);
      std::sort(scales.begin(), scales.end());
      report.scale_p50 = scales[scales.size() / 2];
      report.scale_min = scales.front();
    }
    for (std::size_t b = 0; b < level_cost_.size() && options_.frame_budget_ms > 0.0; ++b)
      if (!level_cost_[b].empty()) report.level_draw_ms.emplace_back(body_names_[b], level_cost_[b]);
    report.software_renderer = software_;
    report.renderer = renderer_name_;
    report.width = options_.width;
    report.height = options_.height;
  }

 private:
  static Window& self(GLFWwindow* w) { return *static_cast<Window*>(glfwGetWindowUserPointer(w)); }

  void open_window(int samples) {
    glfwWindowHint(GLFW_SAMPLES, samples);
    const std::string title = fmt::format("tactus: {}", model_.name);
    window_ = glfwCreateWindow(options_.width, options_.height, title.c_str(), nullptr, nullptr);
    if (!window_ && samples > 0) {  // some servers offer no multisampled visual
      glfwWindowHint(GLFW_SAMPLES, 0);
      window_ = glfwCreateWindow(options_.width, options_.height, title.c_str(), nullptr, nullptr);
    }
    if (!window_)
      throw InputError(fmt::format("--view: no OpenGL 3.3 core window could be opened ({}); the viewer needs a "
                                   "display with OpenGL 3.3 (Mesa's llvmpipe will do)",
                                   g_glfw_error));
    glfwMakeContextCurrent(window_);
  }

  int modifiers() const {
    int mods = 0;
    if (glfwGetKey(window_, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS || glfwGetKey(window_, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS)
      mods |= GLFW_MOD_SHIFT;
    if (glfwGetKey(window_, GLFW_KEY_LEFT_CONTROL) == GLFW_PRESS || glfwGetKey(window_, GLFW_KEY_RIGHT_CONTROL) == GLFW_PRESS)
      mods |= GLFW_MOD_CONTROL;
    return mods;
  }

  // --- input: GLFW's callbacks and the script's commands both come here -------------------

  // Events the panel takes (a click on a button) do not reach the scene; synthetic events
  // bypass that test, since the real pointer may rest over the panel meanwhile.
  void on_button(int button, int action, int mods, bool synthetic) {
    if (button < 0 || button > 2) return;
    if (action == GLFW_PRESS) {
      if (!synthetic && ImGui::GetIO().WantCaptureMouse) return;
      buttons_ |= 1u << button;
      drag_mods_ = mods;
    } else if (action == GLFW_RELEASE) {
      buttons_ &= ~(1u << button);
    }
  }

  void on_cursor(double x, double y) {
    const double dx = x - cursor_x_, dy = y - cursor_y_;
    cursor_x_ = x;
    cursor_y_ = y;
    if (!cursor_known_) {
      cursor_known_ = true;
      return;
    }
    if (buttons_ & (1u << GLFW_MOUSE_BUTTON_LEFT)) {
      const double mpp = metres_per_pixel();
      if (drag_mods_ & GLFW_MOD_SHIFT)
        move_finger(-dy * mpp * forward());  // dragging up pushes away from the viewer
      else
        move_finger(mpp * (dx * camera_.right() - dy * camera_.up()));
    }
    if (buttons_ & (1u << GLFW_MOUSE_BUTTON_RIGHT)) camera_.orbit(-dx * kOrbitDegreesPerPixel, dy * kOrbitDegreesPerPixel);
    if (buttons_ & (1u << GLFW_MOUSE_BUTTON_MIDDLE)) {
      int w = 0, h = 0;
      glfwGetWindowSize(window_, &w, &h);
      if (h > 0) camera_.pan(-dx / h, dy / h);
    }
  }

  void on_scroll(double notches, int mods, bool synthetic) {
    if (!synthetic && ImGui::GetIO().WantCaptureMouse) return;
    if (mods & GLFW_MOD_CONTROL) {
      camera_.zoom(std::pow(kZoomPerNotch, notches));
      return;
    }
    // A notch moves the finger a third of its radius (2 mm for the nodule scene's 6 mm).
    const double step = finger_radius_ > 0.0 ? finger_radius_ / 3.0 : 0.002;
    move_finger(notches * step * forward());
  }

  void on_key(int key, int action, int /*mods*/, bool synthetic) {
    if (action != GLFW_PRESS) return;
    if (!synthetic && ImGui::GetIO().WantCaptureKeyboard) return;
    switch (key) {
      case GLFW_KEY_R: camera_ = home_camera_; break;
      case GLFW_KEY_F: finger_ = home_finger_; break;
      case GLFW_KEY_T: view_.reveal = !view_.reveal; break;
      case GLFW_KEY_W: view_.wireframe = !view_.wireframe; break;
      case GLFW_KEY_H: panel_visible_ = !panel_visible_; break;
      case GLFW_KEY_E:
      case GLFW_KEY_SPACE: emergency_stop(); break;
      case GLFW_KEY_P: view_.show_planes = !view_.show_planes; break;
      case GLFW_KEY_B: view_.show_bvh = !view_.show_bvh; break;
      case GLFW_KEY_L: view_.show_levels = !view_.show_levels; break;
      case GLFW_KEY_G: view_.graphics_levels = !view_.graphics_levels; break;
      case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(window_, GLFW_TRUE); break;
      default: break;
    }
  }

  /// Every device's force off at its next frame, for the rest of the run.
  void emergency_stop() {
    if (stopped_) return;
    live_.request_emergency_stop();
    stopped_ = true;
    std::printf("view: emergency stop\n");
    std::fflush(stdout);
  }

  [[nodiscard]] Vec3 forward() const { return (camera_.target - camera_.eye()).normalized(); }

  /// Scene metres per window pixel at the finger's depth, so the finger follows the cursor.
  [[nodiscard]] double metres_per_pixel() const {
    int w = 0, h = 0;
    glfwGetWindowSize(window_, &w, &h);
    const double depth = std::max((finger_ - camera_.eye()).dot(forward()), 0.1 * camera_.distance);
    return 2.0 * depth * std::tan(camera_.fov_y * std::numbers::pi / 360.0) / std::max(h, 1);
  }

  /// Keeps the finger within a few scene sizes of the scene, whatever the mouse does.
  void move_finger(const Vec3& delta) {
    if (!mouse_ || !delta.allFinite()) return;
    const Vec3 margin = (scene_box_.max - scene_box_.min).cwiseMax(Vec3::Constant(0.01));
    finger_ = (finger_ + delta).cwiseMax(scene_box_.min - margin).cwiseMin(scene_box_.max + margin);
  }

  // --- the script -------------------------------------------------------------------------

  /// Runs commands until one waits; called once per frame before drawing.
  void run_script() {
    while (next_ < script_.size()) {
      const ScriptCommand& c = script_[next_];
      switch (c.op) {
        case ScriptOp::wait:
          if (!waiting_) {
            waiting_ = true;
            wait_until_ = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(c.a));
          }
          if (Clock::now() < wait_until_) return;
          waiting_ = false;
          break;
        case ScriptOp::frames:
          if (!waiting_) {
            waiting_ = true;
            frames_left_ = static_cast<std::uint64_t>(c.a);
          }
          if (frames_left_ > 0) {
            --frames_left_;
            return;
          }
          waiting_ = false;
          break;
        case ScriptOp::move: on_cursor(c.a, c.b); break;
        case ScriptOp::press: on_button(c.button, GLFW_PRESS, c.mods, true); break;
        case ScriptOp::release: on_button(c.button, GLFW_RELEASE, 0, true); break;
        case ScriptOp::scroll: on_scroll(c.a, c.mods, true); break;
        case ScriptOp::key: on_key(c.key, GLFW_PRESS, 0, true); break;
        case ScriptOp::print: print_state(); break;
        case ScriptOp::surface:
        case ScriptOp::material:
          try {
            if (c.op == ScriptOp::surface)
              live_.set_surface(0, c.a, c.b, c.c);
            else
              live_.set_material(static_cast<std::size_t>(c.button), c.a, c.b);
            std::printf("view: edited at t = %.3f s\n", feed_.build().t);
            std::fflush(stdout);
          } catch (const InputError& e) {
            throw InputError(SourceLocation{options_.script->string(), c.line, {}, {}}, e.what());
          }
          break;
        case ScriptOp::screenshot:
          screenshot_ = c.text;  // taken after this frame is drawn
          ++next_;
          return;
        case ScriptOp::scene:
          next_scene_ = c.text;
          quit_ = true;
          return;
        case ScriptOp::quit: quit_ = true; return;
      }
      ++next_;
    }
  }

  void print_state() {
    const std::vector<ToolView> tools = feed_.tools();
    if (tools.empty() || !tools.front().seen) {
      std::printf("view: no haptic frame seen yet\n");
    } else {
      const ToolView& t = tools.front();
      std::printf("view: finger at (%.5f, %.5f, %.5f) m, force %.4f N, %s; visual %.2f Hz\n", t.device_position.x(),
                  t.device_position.y(), t.device_position.z(), t.force.norm(), t.touching ? "touching" : "free",
                  visual_rate_);
    }
    std::fflush(stdout);
  }

  // --- painting property images ------------------------------------------------------------

  [[nodiscard]] bool paintable() const {
    for (const auto& o : touchables_.objects)
      if (o && o->properties) return true;
    return false;
  }

  /// While the brush is on, the first tool paints where it touches (the haptic loop feels it
  /// at its next lookup: the images are shared and written lock-free).
  void paint(const std::vector<ToolView>& tools) {
    if (!brush_.on || tools.empty() || !tools.front().touching) return;
    const std::string body = paint_at(touchables_, model_, tools.front().contact_point, brush_);
    if (!body.empty()) painted_ = fmt::format("painting {}", body);
  }

  void save_images() {
    const std::filesystem::path folder = std::filesystem::path(model_.source).parent_path();
    try {
      const auto files = save_property_images(touchables_, model_, folder);
      painted_.clear();
      for (const auto& f : files) painted_ += (painted_.empty() ? "saved " : ", ") + f.string();
      std::printf("view: %s\n", painted_.c_str());
      std::fflush(stdout);
    } catch (const InputError& e) {
      painted_ = e.what();
    }
  }

  // --- drawing ----------------------------------------------------------------------------

  void draw_frame() {
    FrameView frame = feed_.build();
    const std::vector<ToolView> tools = feed_.tools();
    if (touchables_.any()) {
      // The debug view shows the haptic loop's levels; otherwise the graphics impostors chosen
      // for this frame by projected size within the triangle budget.
      int fb_width = 0, fb_height = 0;
      glfwGetFramebufferSize(window_, &fb_width, &fb_height);
      const double focal = 0.5 * std::max(fb_height, 1) / std::tan(0.5 * camera_.fov_y * M_PI / 180.0);
      if (view_.show_levels)
        show_levels(touchables_, feed_.levels(), true, frame);
      else if (view_.graphics_levels)
        show_levels(touchables_, choose_graphics_levels(touchables_, camera_.eye(), focal, level_cost_, level_budget()),
                    false, frame);
    }
    debug_.add(tools, view_, frame);
    paint(tools);
    int width = 0, height = 0;
    glfwGetFramebufferSize(window_, &width, &height);
    if (width <= 0 || height <= 0) return;  // minimised
    // The scene at the scale the frame budget allows, stretched over the window; the panel and
    // the overlay at the window's own resolution, so their text stays sharp.
    scale_ = governor_ ? governor_->scale() : 1.0;
    if (scale_ < 1.0) {
      const int scene_width = std::max(1, static_cast<int>(std::lround(scale_ * width)));
      const int scene_height = std::max(1, static_cast<int>(std::lround(scale_ * height)));
      scene_target_.bind(scene_width, scene_height);
      renderer_->render(frame, camera_, view_, scene_width, scene_height);
      scene_target_.stretch_to(0, width, height);
    } else {
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      renderer_->render(frame, camera_, view_, width, height);
    }
    glViewport(0, 0, width, height);

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    if (panel_visible_) {
      PanelInputs in;
      in.scene = model_.name;
      in.mouse_device = mouse_device_;
      in.recording = recording_;
      in.visual_rate = visual_rate_;
      in.frame_ms = last_frame_ms_;
      in.t = frame.t;
      in.tools = tools;
      in.live = &live_;
      in.body_names = body_names_;
      in.device_names = device_names_;
      in.emergency_stopped = stopped_;
      in.scenes = scenes_;
      in.samples = feed_.samples();
      in.events = feed_.events();
      if (paintable()) in.brush = &brush_;
      in.painted = painted_;
      const PanelActions a = draw_panel(in, view_);
      if (a.save_images) save_images();
      if (a.reset_camera) camera_ = home_camera_;
      if (a.reset_finger) finger_ = home_finger_;
      if (a.close) glfwSetWindowShouldClose(window_, GLFW_TRUE);
      if (a.emergency_stop) emergency_stop();
      if (!a.switch_to.empty()) {
        next_scene_ = a.switch_to;
        glfwSetWindowShouldClose(window_, GLFW_TRUE);
      }
    }
    {
      // The overlay in window coordinates (ImGui's), laid out in framebuffer pixels.
      int window_width = 0, window_height = 0;
      glfwGetWindowSize(window_, &window_width, &window_height);
      std::optional<std::pair<double, double>> hovered;
      if (cursor_known_ && window_width > 0 && window_height > 0 && !ImGui::GetIO().WantCaptureMouse)
        hovered = std::pair{cursor_x_ * width / window_width, cursor_y_ * height / window_height};
      paint_with_imgui(build_overlay(frame, camera_, view_, width, height, hovered),
                       static_cast<float>(window_width) / static_cast<float>(width));
    }
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

    if (!screenshot_.empty()) {
      glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
      glReadBuffer(GL_BACK);
      png::write_rgb(screenshot_, width, height, read_rgb(width, height));
      std::printf("view: screenshot %s (%dx%d; %zu constraint planes, %zu BVH boxes)\n", screenshot_.c_str(), width,
                  height, frame.quads.size(), frame.boxes.size());
      std::fflush(stdout);
      screenshot_.clear();
    }
    glfwSwapBuffers(window_);
  }

  const scene::Model& model_;
  const WindowOptions& options_;
  VisualFeed& feed_;
  MouseChannel* mouse_;
  haptics::WorkspaceMap map_;
  std::string mouse_device_, recording_;
  bool imgui_ = false;
  GLFWwindow* window_ = nullptr;
  std::unique_ptr<Renderer> renderer_;

  Aabb scene_box_;
  OrbitCamera camera_, home_camera_;
  ViewOptions view_;
  bool panel_visible_ = true;
  double finger_radius_ = 0.0;
  Vec3 finger_ = Vec3::Zero(), home_finger_ = Vec3::Zero();  ///< the mouse's target, scene [m]

  unsigned buttons_ = 0;
  int drag_mods_ = 0;
  double cursor_x_ = 0.0, cursor_y_ = 0.0;
  bool cursor_known_ = false;

  std::vector<ScriptCommand> script_;
  std::size_t next_ = 0;
  bool waiting_ = false, quit_ = false;
  Clock::time_point wait_until_;
  std::uint64_t frames_left_ = 0;
  std::string screenshot_;

  double visual_rate_ = 0.0, last_frame_ms_ = 0.0;

  runtime::LiveParameters& live_;
  DebugViews debug_;
  /// The touchable objects' graphics impostors share this part of the frame budget by their
  /// measured draw times; the rest is the pixels' (the scale) and the panel's.
  static constexpr double kObjectShare = 0.4;
  /// Without a frame budget, the triangles the objects may draw in a frame.
  static constexpr double kTriangleBudget = 60'000;
  /// The levels' share of the frame in their measured draw time (one pass), or in triangles.
  /// With shadows each level is drawn twice, the second time depth only into the shadow map:
  /// charged as a second pass, the share halves.
  [[nodiscard]] double level_budget() const {
    if (options_.frame_budget_ms <= 0.0) return kTriangleBudget;
    return kObjectShare * options_.frame_budget_ms / (view_.shadows ? 2.0 : 1.0);
  }
  const compile::Touchables& touchables_;
  LevelCosts level_cost_;
  std::string renderer_name_;
  bool software_ = false;
  std::optional<ResolutionGovernor> governor_;
  SceneTarget scene_target_;
  double scale_ = 1.0;
  PaintBrush brush_;
  std::string painted_;
  bool stopped_ = false;
  std::vector<std::string> body_names_, device_names_, scenes_;
  std::string next_scene_;
};

}  // namespace

bool mouse_may_drive(const scene::Model& model, std::size_t index, const runtime::SessionOptions& options) {
  if (index >= model.devices.size()) return false;
  const scene::Device& d = model.devices[index];
  if (options.replay.count(d.name)) return false;
  return std::holds_alternative<scene::ScriptedDevice>(d.source) ||
         std::holds_alternative<scene::SimulatedOperatorDevice>(d.source);
}

runtime::SessionReport run_with_window(const scene::Model& model, runtime::SessionOptions options,
                                       const WindowOptions& window_options, std::atomic<bool>& stop,
                                       WindowReport& report) {
  VisualFeed feed(model);
  const bool mouse = window_options.mouse && mouse_may_drive(model, 0, options);
  const haptics::WorkspaceMap map = model.devices.empty() ? haptics::WorkspaceMap{} : compile::workspace_map(model.devices[0]);
  report.mouse_device = mouse ? model.devices[0].name : std::string();
  // The channel is built before the window (which sets its start) and outlives the run.
  MouseChannel channel(Vec3::Zero());
  // Edits from the panel; they outlive the run, which reads them.
  runtime::LiveParameters live(model);
  // Built here and shared with the run: the panel's brush paints the images the haptic loop reads.
  const compile::Touchables touchables = compile::load_touchables(model);
  options.touchables = &touchables;
  Window window(model, window_options, feed, mouse ? &channel : nullptr, map, report.mouse_device,
                options.record ? options.record->string() : std::string(), live, touchables);
  options.live = &live;
  channel.set(window.home_device_position());
  options.visual = &feed;
  options.interrupt = &stop;
  if (mouse)
    options.device_override = [&channel](const scene::Model& m, std::size_t index) -> std::unique_ptr<haptics::Device> {
      if (index != 0) return nullptr;
      return std::make_unique<MouseDevice>(channel, compile::device_limits(m.devices[index]));
    };

  runtime::SessionReport session;
  std::exception_ptr failure;
  std::atomic<bool> run_over{false};
  std::thread run([&] {
    try {
      session = runtime::run_session(model, options);
    } catch (...) {
      failure = std::current_exception();
    }
    run_over.store(true, std::memory_order_release);
  });
  try {
    window.loop(stop, run_over, report);
  } catch (...) {
    stop.store(true);
    run.join();
    throw;
  }
  run.join();
  report.next_scene = window.next_scene();
  if (failure) std::rethrow_exception(failure);
  return session;
}

std::vector<std::string> scene_files(const std::filesystem::path& folder) {
  std::vector<std::string> out;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder.empty() ? "." : folder, error))
    if (entry.is_regular_file(error) && entry.path().extension() == ".toml") out.push_back(entry.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::string format_window_report(const WindowReport& r) {
  std::string out = fmt::format("visual loop: {} frames in {:.2f} s, {:.1f} Hz; frame time p50 {:.2f} ms, p99 {:.2f} ms{}\n",
                                r.frames, r.seconds, r.rate, r.frame_p50_ms, r.frame_p99_ms,
                                r.mouse_device.empty() ? "" : fmt::format("; the mouse drove '{}'", r.mouse_device));
  if (r.frames > 0)
    out += fmt::format("  scene drawn at {:.2f} of {} x {} (p50; least {:.2f}), {} renderer '{}'\n", r.scale_p50, r.width,
                       r.height, r.scale_min, r.software_renderer ? "software" : "hardware", r.renderer);
  for (const auto& [body, ms] : r.level_draw_ms) {
    std::string levels;
    for (const double t : ms) levels += fmt::format("{}{:.3f}", levels.empty() ? "" : " / ", t);
    out += fmt::format("  graphics levels of {}, measured draw time coarse to fine: {} ms\n", body, levels);
  }
  return out;
}

}  // namespace tactus::viewer
