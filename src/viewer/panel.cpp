#include "viewer/panel.hpp"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <tuple>

#include "core/error.hpp"

namespace tactus::viewer {
namespace {

constexpr double kPlotSeconds = 10.0;  // the plots show the last 10 s

/// One plot of a sample field over the last kPlotSeconds, with its newest and largest value.
template <class Field>
void plot(const char* label, const char* unit, const std::vector<PlotSample>& samples, Field field) {
  std::vector<float> values;
  const double since = samples.empty() ? 0.0 : samples.back().t - kPlotSeconds;
  float largest = 0.0f;
  for (const PlotSample& s : samples)
    if (s.t >= since) {
      values.push_back(static_cast<float>(field(s)));
      largest = std::max(largest, values.back());
    }
  char overlay[96];
  std::snprintf(overlay, sizeof overlay, "now %.3g %s, max %.3g %s", values.empty() ? 0.0 : values.back(), unit,
                static_cast<double>(largest), unit);
  ImGui::TextUnformatted(label);
  // Two points a pixel column (its least and largest sample) look the same as all 2,000 and
  // cost a software renderer a tenth of the lines.
  const float width = ImGui::GetContentRegionAvail().x;
  values = min_max_envelope(values, static_cast<std::size_t>(std::max(width, 1.0f)));
  ImGui::PlotLines((std::string("##") + label).c_str(), values.data(), static_cast<int>(values.size()), 0, overlay,
                   0.0f, std::max(largest * 1.1f, 1e-6f), ImVec2(width, 70.0f));
}

/// A double slider; true when moved.
bool slider(const char* label, double& value, double lo, double hi, const char* format, bool logarithmic = false) {
  return ImGui::SliderScalar(label, ImGuiDataType_Double, &value, &lo, &hi, format,
                             logarithmic ? ImGuiSliderFlags_Logarithmic : ImGuiSliderFlags_None);
}

/// Material and surface edits: each slider writes the run's live parameters at once.
void edit_parameters(const PanelInputs& in, std::string& error) {
  runtime::LiveParameters& live = *in.live;
  auto guarded = [&](auto&& edit) {
    try {
      edit();
      error.clear();
    } catch (const InputError& e) {
      error = e.what();
    }
  };
  for (std::size_t b = 0; b < in.body_names.size() && b < runtime::LiveParameters::kMaxBodies; ++b) {
    if (!live.material_editable(b)) continue;
    const runtime::LiveParameters::Material& scene = live.scene_materials().body[b];
    const runtime::LiveParameters::Material& now = live.edited_materials().body[b];
    ImGui::PushID(static_cast<int>(b));
    ImGui::Text("body '%s'", in.body_names[b].c_str());
    double e_kpa = now.young_modulus * 1e-3;
    double alpha = now.damping_set ? now.damping : scene.damping;
    const bool moved_e = slider("E [kPa]", e_kpa, scene.young_modulus * 1e-4, scene.young_modulus * 1e-2, "%.3g", true);
    const bool moved_alpha = slider("damping [1/s]", alpha, 0.0, std::max(50.0, 4.0 * scene.damping), "%.3g");
    if (moved_e || moved_alpha)
      guarded([&] { live.set_material(b, e_kpa * 1e3, moved_alpha || now.damping_set ? alpha : -1.0); });
    if (ImGui::Button("scene values")) guarded([&] { live.set_material(b, scene.young_modulus, -1.0); });
    ImGui::PopID();
  }
  for (std::size_t d = 0; d < in.device_names.size() && d < runtime::LiveParameters::kMaxDevices; ++d) {
    const runtime::LiveParameters::SurfaceKind kind = live.surface_kind(d);
    if (kind == runtime::LiveParameters::SurfaceKind::none) continue;
    const runtime::LiveParameters::Surface& scene = live.scene_surface(d);
    runtime::LiveParameters::Surface now = live.edited_surface(d);
    ImGui::PushID(1000 + static_cast<int>(d));
    ImGui::Text("surface under '%s' (%s)", in.device_names[d].c_str(),
                kind == runtime::LiveParameters::SurfaceKind::proxy ? "proxy" : "penalty");
    bool moved = slider("stiffness [N/m]", now.stiffness, 1.0, live.max_stiffness(d), "%.0f", true);
    if (kind == runtime::LiveParameters::SurfaceKind::proxy) {
      moved |= slider("static friction", now.static_friction, 0.0, 1.5, "%.2f");
      now.kinetic_friction = std::min(now.kinetic_friction, now.static_friction);
      moved |= slider("kinetic friction", now.kinetic_friction, 0.0, now.static_friction, "%.2f");
    }
    if (moved)
      guarded([&] { live.set_surface(d, now.stiffness, now.static_friction, std::min(now.kinetic_friction, now.static_friction)); });
    if (ImGui::Button("scene values"))
      guarded([&] { live.set_surface(d, scene.stiffness, scene.static_friction, scene.kinetic_friction); });
    ImGui::PopID();
  }
  if (!error.empty()) ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.3f, 1.0f), "%s", error.c_str());
}

}  // namespace

std::vector<float> min_max_envelope(std::span<const float> values, std::size_t columns) {
  if (columns == 0 || values.size() <= 2 * columns) return {values.begin(), values.end()};
  std::vector<float> out;
  out.reserve(2 * columns);
  for (std::size_t c = 0; c < columns; ++c) {
    const std::size_t begin = c * values.size() / columns, end = (c + 1) * values.size() / columns;
    const auto [lo, hi] = std::minmax_element(values.begin() + static_cast<std::ptrdiff_t>(begin),
                                              values.begin() + static_cast<std::ptrdiff_t>(end));
    // In time order, so the line runs through the column the way the samples did.
    if (lo < hi) {
      out.push_back(*lo);
      out.push_back(*hi);
    } else {
      out.push_back(*hi);
      out.push_back(*lo);
    }
  }
  return out;
}

const std::vector<std::pair<const char*, const char*>>& shortcuts() {
  static const std::vector<std::pair<const char*, const char*>> list = {
      {"left drag", "move the finger in the view plane"},
      {"wheel / shift + left drag", "move the finger in depth"},
      {"right drag", "orbit the camera"},
      {"middle drag", "pan the camera"},
      {"ctrl + wheel", "zoom"},
      {"R", "reset the camera"},
      {"F", "put the finger back above the scene"},
      {"T", "transparency (reveal what lies under)"},
      {"W", "wireframe"},
      {"E / space", "emergency stop: every device's force off until the run ends"},
      {"P", "constraint planes of the contacts"},
      {"B", "BVH boxes (top levels)"},
      {"L", "touchable objects at the haptic loop's impostor levels, coloured by level"},
      {"G", "graphics impostors chosen each frame (off: every object at its finest)"},
      {"H", "hide / show this panel"},
      {"Esc", "close the window, end the run"},
  };
  return list;
}

PanelActions draw_panel(const PanelInputs& in, ViewOptions& view) {
  PanelActions actions;
  ImGui::SetNextWindowPos(ImVec2(10.0f, 10.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(370.0f, 640.0f), ImGuiCond_FirstUseEver);
  ImGui::Begin("Tactus");
  ImGui::Text("scene %s, t = %.2f s", in.scene.c_str(), in.t);
  ImGui::Text("visual %.1f Hz (frame %.1f ms)", in.visual_rate, in.frame_ms);
  if (in.mouse_device.empty())
    ImGui::TextUnformatted("the scene's device drives the tool (no mouse)");
  else
    ImGui::Text("the mouse drives '%s'", in.mouse_device.c_str());
  // Every device: a hand and a needle both push on the user.
  for (const ToolView& tool : in.tools) {
    if (!tool.seen) continue;
    const Vec3& p = tool.device_position;
    ImGui::Text("%s (%.1f, %.1f, %.1f) mm %s, force %.3f N", tool.name.c_str(), p.x() * 1e3, p.y() * 1e3, p.z() * 1e3,
                tool.touching ? "touching" : "free", tool.force.norm());
  }

  if (in.live) {
    if (in.emergency_stopped) {
      ImGui::TextColored(ImVec4(1.0f, 0.3f, 0.25f, 1.0f), "EMERGENCY STOP: forces off until the run ends");
    } else {
      ImGui::PushStyleColor(ImGuiCol_Button, ImVec4(0.75f, 0.1f, 0.1f, 1.0f));
      if (ImGui::Button("EMERGENCY STOP (E / space)")) actions.emergency_stop = true;
      ImGui::PopStyleColor();
    }
  }

  if (ImGui::CollapsingHeader("Plots", ImGuiTreeNodeFlags_DefaultOpen)) {
    plot("force on the hand", "N", in.samples, [](const PlotSample& s) { return s.force; });
    plot("haptic frame compute time", "us", in.samples, [](const PlotSample& s) { return s.compute_us; });
  }
  if (ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::Checkbox("transparency (T)", &view.reveal);
    ImGui::SameLine();
    ImGui::Checkbox("wireframe (W)", &view.wireframe);
    ImGui::Checkbox("shadows", &view.shadows);
    ImGui::SameLine();
    ImGui::Checkbox("pressure", &view.show_pressure);
    ImGui::SameLine();
    ImGui::Checkbox("force arrow", &view.show_forces);
    ImGui::Checkbox("constraint planes (P)", &view.show_planes);
    ImGui::SameLine();
    ImGui::Checkbox("BVH (B)", &view.show_bvh);
    if (view.show_bvh) {
      ImGui::SameLine();
      ImGui::SetNextItemWidth(80.0f);
      ImGui::SliderInt("levels", &view.bvh_levels, 0, 8);
    }
    ImGui::Checkbox("haptic levels (L)", &view.show_levels);
    ImGui::SameLine();
    ImGui::Checkbox("graphics impostors (G)", &view.graphics_levels);
    if (ImGui::Button("reset camera (R)")) actions.reset_camera = true;
    ImGui::SameLine();
    if (ImGui::Button("reset finger (F)")) actions.reset_finger = true;
    ImGui::SameLine();
    if (ImGui::Button("quit")) actions.close = true;
  }
  if (in.brush && ImGui::CollapsingHeader("Paint property images", ImGuiTreeNodeFlags_DefaultOpen)) {
    // Seed 001's authoring: the tool is the brush; what it paints is felt at once.
    PaintBrush& b = *in.brush;
    ImGui::Checkbox("paint where the tool touches", &b.on);
    slider("radius [m]", b.radius, 0.001, 0.1, "%.3f", true);
    using property_images::Channel;
    const std::array<std::tuple<Channel, const char*, double, double, const char*, bool>, 8> channels{{
        {Channel::stiffness, "stiffness [N/m]", 10.0, 5000.0, "%.0f", true},
        {Channel::static_friction, "static friction", 0.0, 2.0, "%.2f", false},
        {Channel::kinetic_friction, "kinetic friction", 0.0, 2.0, "%.2f", false},
        {Channel::damping, "damping [N s/m]", 0.0, 20.0, "%.2f", false},
        {Channel::roughness_amplitude, "roughness [m]", 1e-6, 1e-3, "%.1e", true},
        {Channel::roughness_wavelength, "wavelength [m]", 1e-3, 0.05, "%.4f", true},
        {Channel::young_modulus, "E for fingers [Pa]", 1e2, 1e7, "%.3g", true},
        {Channel::poisson_ratio, "poisson ratio", 0.0, 0.5, "%.2f", false},
    }};
    for (const auto& [channel, label, lo, hi, format, logarithmic] : channels) {
      const auto bit = property_images::mask_of(channel);
      bool use = (b.mask & bit) != 0;
      ImGui::PushID(label);
      if (ImGui::Checkbox("##use", &use)) b.mask = static_cast<property_images::ChannelMask>(use ? b.mask | bit : b.mask & ~bit);
      ImGui::SameLine();
      slider(label, b.values[channel], lo, hi, format, logarithmic);
      ImGui::PopID();
    }
    // μk ≤ μs, as every material must have.
    b.values[Channel::kinetic_friction] = std::min(b.values[Channel::kinetic_friction], b.values[Channel::static_friction]);
    if (ImGui::Button("save images")) actions.save_images = true;
    if (!in.painted.empty()) ImGui::TextWrapped("%s", in.painted.c_str());
  }
  if (in.live && ImGui::CollapsingHeader("Material and surface (live)", ImGuiTreeNodeFlags_DefaultOpen)) {
    static std::string error;  // the panel's one ImGui context lives on one thread
    edit_parameters(in, error);
  }
  if (ImGui::CollapsingHeader("Safety and contact events", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::BeginChild("events", ImVec2(0.0f, 110.0f), true);
    if (in.events.empty()) ImGui::TextUnformatted("none");
    for (const std::string& e : in.events) ImGui::TextUnformatted(e.c_str());
    if (ImGui::GetScrollY() >= ImGui::GetScrollMaxY()) ImGui::SetScrollHereY(1.0f);
    ImGui::EndChild();
  }
  if (ImGui::CollapsingHeader("Recording")) {
    if (in.recording.empty())
      ImGui::TextUnformatted("not recording (start the run with --record FILE)");
    else
      ImGui::Text("recording to %s", in.recording.c_str());
  }
  if (!in.scenes.empty() && ImGui::CollapsingHeader("Scenes")) {
    ImGui::TextWrapped("Ends this run (its report is printed) and starts the chosen scene.");
    for (const std::string& s : in.scenes)
      if (ImGui::Selectable(std::filesystem::path(s).filename().string().c_str(), false)) actions.switch_to = s;
  }
  if (ImGui::CollapsingHeader("Shortcuts")) {
    for (const auto& [keys, what] : shortcuts()) ImGui::BulletText("%s: %s", keys, what);
  }
  ImGui::End();
  return actions;
}

}  // namespace tactus::viewer
