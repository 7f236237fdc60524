// Ten camera bookmarks per level, kept in the user's settings folder (bookmarks.json beside
// config.json) so that they outlive the session: { "<level's absolute path>": { "1": "(x y z)
// pitch yaw roll", ... } }. Ctrl+digit stores the camera, Alt+digit goes back to it.
#pragma once

#include "renderer/camera.h"
#include "viewer/overlay.h"

#include <filesystem>
#include <optional>
#include <string>

namespace bt {

class Bookmarks {
public:
  // `file` empty: bookmarks last for the session only.
  Bookmarks(std::filesystem::path file, std::string level) : file_(std::move(file)), level_(std::move(level)) {}

  // Slot 0..9; nullopt when it holds none (or the file cannot be read: what() says why).
  std::optional<CameraPose> get(int slot) const;
  // Stores the pose and writes the file (to a temporary name, then renamed); throws naming the
  // file when it cannot be written. The slot is kept for the session either way.
  void set(int slot, const CameraPose& pose);

  // A bookmark key: Ctrl+digit (`store`) keeps `now` in the slot, Alt+digit sets `goTo` to the
  // slot's camera. Returns what the overlay says (stored, gone to, empty slot, or why the file
  // could not be written: the viewer goes on).
  OverlayMessage press(int slot, bool store, const CameraPose& now, std::optional<CameraPose>& goTo);

private:
  std::filesystem::path file_;
  std::string level_;
  std::optional<CameraPose> session_[10];
};

} // namespace bt
