#include "importers/game/file_system.h"

#include "scene/names.h"

#include <algorithm>
#include <fstream>
#include <set>

namespace bt::game {

namespace fs = std::filesystem;

bool staysInTheGame(std::string_view name) {
  const fs::path relative{std::string(name)};
  if (name.empty() || relative.is_absolute()) return false;
  for (const auto& part : relative)
    if (part == "..") return false;
  return true;
}

void FileSystem::addGameDir(const fs::path& dir, const std::vector<std::string>& archiveExtensions) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return;
  for (const Mount& m : mounts_)
    if (!m.archive && m.dir == dir) return;
  mounts_.push_back(Mount{dir, nullptr});
  std::vector<fs::path> archives;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string ext = lowercase(entry.path().extension().string());
    const bool wanted = std::find(archiveExtensions.begin(), archiveExtensions.end(), ext) != archiveExtensions.end();
    const bool pk3dir = ext == ".pk3dir" && entry.is_directory(ec);
    if ((wanted && entry.is_regular_file(ec)) || pk3dir) archives.push_back(entry.path());
  }
  // Quake loads pak0, pak1, ... and searches the last loaded first; Quake 3 sorts its pk3s by
  // name and searches them the same way. Both amount to: descending by name.
  std::sort(archives.begin(), archives.end(),
            [](const fs::path& a, const fs::path& b) { return lowercase(a.filename().string()) > lowercase(b.filename().string()); });
  for (const fs::path& a : archives) {
    if (fs::is_directory(a, ec))
      mounts_.push_back(Mount{a, nullptr});
    else
      try {
        addArchive(a);
      } catch (const ImportError& e) {
        skipped_.push_back({Severity::Warning, e.diagnostic().file, 0, 0, "archive skipped: " + e.diagnostic().message});
      }
  }
}

void FileSystem::addArchive(const fs::path& archive) {
  for (const Mount& m : mounts_)
    if (m.archive && m.archive->path() == archive) return;
  std::unique_ptr<Archive> opened = openArchive(archive);
  if (opened) mounts_.push_back(Mount{{}, std::move(opened)});
}

const FileSystem::Mount* FileSystem::mountHolding(std::string_view name, fs::path* looseFile) const {
  if (!staysInTheGame(name)) return nullptr;
  const fs::path relative{std::string(name)};
  for (const Mount& m : mounts_) {
    if (m.archive) {
      if (m.archive->contains(name)) return &m;
      continue;
    }
    std::error_code ec;
    const fs::path file = m.dir / relative;
    if (fs::is_regular_file(file, ec)) {
      if (looseFile) *looseFile = file;
      return &m;
    }
  }
  return nullptr;
}

std::optional<std::vector<uint8_t>> FileSystem::read(std::string_view name) const {
  fs::path loose;
  const Mount* m = mountHolding(name, &loose);
  if (!m) return std::nullopt;
  if (m->archive) return m->archive->read(name);
  std::ifstream in(loose, std::ios::binary);
  if (!in) return std::nullopt;
  return std::vector<uint8_t>{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::optional<fs::path> FileSystem::fileHolding(std::string_view name) const {
  fs::path loose;
  const Mount* m = mountHolding(name, &loose);
  if (!m) return std::nullopt;
  return m->archive ? m->archive->path() : loose;
}

std::optional<std::string> FileSystem::describe(std::string_view name) const {
  fs::path loose;
  const Mount* m = mountHolding(name, &loose);
  if (!m) return std::nullopt;
  return m->archive ? m->archive->path().string() + ":" + std::string(name) : loose.string();
}

std::vector<std::string> FileSystem::list(std::string_view folder, std::string_view suffix) const {
  const std::string prefix = folder.empty() ? "" : lowercase(folder) + "/";
  const std::string lowerSuffix = lowercase(suffix);
  std::set<std::string> seen;
  std::vector<std::string> out;
  auto consider = [&](const std::string& name) {
    const std::string lower = lowercase(name);
    if (lower.starts_with(prefix) && lower.ends_with(lowerSuffix) && seen.insert(lower).second) out.push_back(name);
  };
  for (const Mount& m : mounts_) {
    if (m.archive) {
      for (const std::string& name : m.archive->names()) consider(name);
      continue;
    }
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(m.dir / std::string(folder), ec))
      consider(prefix.empty() ? entry.path().filename().string() : std::string(folder) + "/" + entry.path().filename().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> FileSystem::describeMounts() const {
  std::vector<std::string> out;
  for (const Mount& m : mounts_) out.push_back(m.archive ? m.archive->path().string() : m.dir.string() + "/");
  return out;
}

} // namespace bt::game
