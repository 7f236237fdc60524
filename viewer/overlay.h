// The viewer's overlay (imgui): the frame's status lines, the messages that come and go
// (a screenshot's path, why it failed, why a level did not load), and a panel listing the
// import's warnings with their file:line:col, the face a click picked. F1 hides it; the image underneath is drawn
// whatever it shows.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace bt {

struct OverlayMessage {
  enum class Kind { Info, Warning, Error };
  Kind kind = Kind::Info;
  std::string text;
};

struct OverlayContent {
  std::vector<std::string> status;           // one line each, plain
  std::vector<std::string> hints;            // the keys, dimmed
  std::vector<OverlayMessage> messages;      // coloured by kind
  std::vector<std::string> warnings;         // the import's diagnostics, formatted
  std::vector<std::string> picked;           // the face a click picked
  std::vector<std::pair<int, float>> styles; // light style, its slider's scale
};

struct StyleMoved {
  int style = 0;
  float scale = 1.0f;
};

// Draws the content into the current imgui frame (between NewFrame and Render). Returns the
// light-style slider let go this frame, if one was.
std::optional<StyleMoved> drawOverlay(const OverlayContent& content);

} // namespace bt
