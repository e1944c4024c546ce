#include "viewer/panel.hpp"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

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
  ImGui::PlotLines((std::string("##") + label).c_str(), values.data(), static_cast<int>(values.size()), 0, overlay,
                   0.0f, std::max(largest * 1.1f, 1e-6f), ImVec2(ImGui::GetContentRegionAvail().x, 70.0f));
}

}  // namespace

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
  if (in.tool.seen) {
    const Vec3& p = in.tool.device_position;
    ImGui::Text("finger (%.1f, %.1f, %.1f) mm %s", p.x() * 1e3, p.y() * 1e3, p.z() * 1e3,
                in.tool.touching ? "touching" : "free");
    ImGui::Text("force %.3f N", in.tool.force.norm());
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
    if (ImGui::Button("reset camera (R)")) actions.reset_camera = true;
    ImGui::SameLine();
    if (ImGui::Button("reset finger (F)")) actions.reset_finger = true;
    ImGui::SameLine();
    if (ImGui::Button("quit")) actions.close = true;
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
  if (ImGui::CollapsingHeader("Shortcuts")) {
    for (const auto& [keys, what] : shortcuts()) ImGui::BulletText("%s: %s", keys, what);
  }
  ImGui::End();
  return actions;
}

}  // namespace tactus::viewer
