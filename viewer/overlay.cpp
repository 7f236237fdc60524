#include "viewer/overlay.h"

#include <imgui.h>

namespace bt {

namespace {
ImVec4 colourOf(OverlayMessage::Kind kind) {
  switch (kind) {
  case OverlayMessage::Kind::Error: return ImVec4(1.0f, 0.35f, 0.3f, 1.0f);
  case OverlayMessage::Kind::Warning: return ImVec4(1.0f, 0.8f, 0.3f, 1.0f);
  default: return ImVec4(0.6f, 1.0f, 0.6f, 1.0f);
  }
}
} // namespace

std::optional<StyleMoved> drawOverlay(const OverlayContent& content) {
  ImGui::SetNextWindowPos(ImVec2(8, 8));
  ImGui::SetNextWindowBgAlpha(0.6f);
  // Wraps long errors (a full path and a parser's message) at most this wide.
  ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(900, 10000));
  ImGui::Begin("brushtrace", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing |
                   ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoMove);
  ImGui::PushTextWrapPos(880.0f);
  for (const std::string& line : content.status) ImGui::TextUnformatted(line.c_str());
  for (const std::string& line : content.hints) ImGui::TextDisabled("%s", line.c_str());
  for (const OverlayMessage& m : content.messages) ImGui::TextColored(colourOf(m.kind), "%s", m.text.c_str());
  if (!content.picked.empty() && ImGui::CollapsingHeader("picked face", ImGuiTreeNodeFlags_DefaultOpen))
    for (const std::string& line : content.picked) ImGui::TextUnformatted(line.c_str());
  if (!content.warnings.empty()) {
    const std::string title = "import warnings (" + std::to_string(content.warnings.size()) + ")";
    if (ImGui::CollapsingHeader(title.c_str()))
      for (const std::string& w : content.warnings) ImGui::TextUnformatted(w.c_str());
  }
  std::optional<StyleMoved> moved;
  if (!content.styles.empty() && ImGui::CollapsingHeader("light styles", ImGuiTreeNodeFlags_DefaultOpen))
    for (auto [style, scale] : content.styles) {
      const std::string label = "style " + std::to_string(style);
      ImGui::SliderFloat(label.c_str(), &scale, 0.0f, 2.0f, "%.2f");
      // On release only: each change reloads the level and bakes its luxels again.
      if (ImGui::IsItemDeactivatedAfterEdit()) moved = StyleMoved{style, scale};
    }
  ImGui::PopTextWrapPos();
  ImGui::End();
  return moved;
}

} // namespace bt
