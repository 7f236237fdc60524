#include "viewer/bookmarks.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <stdexcept>

namespace bt {

namespace fs = std::filesystem;

namespace {

// The whole file: an empty object when there is none yet, nullopt when it is not a JSON object
// (then it is left as it is: it may be the user's, damaged, and worth mending by hand).
std::optional<nlohmann::json> readAll(const fs::path& file) {
  std::error_code ec;
  if (!fs::exists(file, ec)) return nlohmann::json::object();
  std::ifstream in(file);
  nlohmann::json all = nlohmann::json::parse(in, nullptr, false);
  if (!in.is_open() || !all.is_object()) return std::nullopt;
  return all;
}

} // namespace

std::optional<CameraPose> Bookmarks::get(int slot) const {
  if (slot < 0 || slot > 9) return std::nullopt;
  if (session_[slot]) return session_[slot];
  if (file_.empty()) return std::nullopt;
  const std::optional<nlohmann::json> all = readAll(file_);
  if (!all) return std::nullopt;
  const auto level = all->find(level_);
  if (level == all->end() || !level->is_object()) return std::nullopt;
  const auto pose = level->find(std::to_string(slot));
  if (pose == level->end() || !pose->is_string()) return std::nullopt;
  auto parsed = parseCameraPose(pose->get<std::string>());
  if (parsed) parsed->source = "bookmark " + std::to_string(slot);
  return parsed;
}

void Bookmarks::set(int slot, const CameraPose& pose) {
  if (slot < 0 || slot > 9) return;
  session_[slot] = pose;
  if (file_.empty()) return;
  std::optional<nlohmann::json> all = readAll(file_);
  if (!all) throw std::runtime_error(file_.string() + ": not a bookmarks file (not a JSON object), left as it is");
  if (!(*all)[level_].is_object()) (*all)[level_] = nlohmann::json::object();
  (*all)[level_][std::to_string(slot)] = formatCameraPose(pose);
  std::error_code ec;
  fs::create_directories(file_.parent_path(), ec);
  const fs::path temporary = file_.string() + ".tmp";
  {
    std::ofstream out(temporary);
    out << all->dump(2) << "\n";
    if (!out) {
      out.close();
      fs::remove(temporary, ec);
      throw std::runtime_error(file_.string() + ": cannot write the bookmarks");
    }
  }
  fs::rename(temporary, file_, ec);
  if (ec) {
    fs::remove(temporary, ec);
    throw std::runtime_error(file_.string() + ": cannot write the bookmarks: " + ec.message());
  }
}

OverlayMessage Bookmarks::press(int slot, bool store, const CameraPose& now, std::optional<CameraPose>& goTo) {
  if (store) {
    try {
      set(slot, now);
      return {OverlayMessage::Kind::Info, "bookmark " + std::to_string(slot) + ": " + formatCameraPose(now)};
    } catch (const std::exception& e) {
      return {OverlayMessage::Kind::Error, std::string("bookmark kept for this session only: ") + e.what()};
    }
  }
  goTo = get(slot);
  if (!goTo)
    return {OverlayMessage::Kind::Warning, "no bookmark " + std::to_string(slot) + " (Ctrl+" + std::to_string(slot) + " stores one)"};
  return {OverlayMessage::Kind::Info, "bookmark " + std::to_string(slot) + ": " + formatCameraPose(*goTo)};
}

} // namespace bt
