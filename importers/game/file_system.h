// One virtual file system over a game's loose folders and archives, searched in the engine's
// order: every file the importers read from a game install comes through here.
#pragma once

#include "importers/game/archive.h"
#include "scene/diagnostics.h"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace bt::game {

class FileSystem {
public:
  // Mounts a game folder below everything mounted so far: first its loose files, then its
  // archives of the given kinds (".pak", ".pk3"; ".pk3dir" folders count as archives), the
  // later by name first (pak1 before pak0, zz.pk3 before aa.pk3), as Quake and Quake 3 load them.
  // A corrupt archive is left out and reported in skipped().
  void addGameDir(const std::filesystem::path& dir, const std::vector<std::string>& archiveExtensions = {".pak", ".pk3"});
  // Mounts one archive below everything mounted so far (nothing if it is mounted already).
  // Throws ImportError naming the archive (and entry) when it is corrupt.
  void addArchive(const std::filesystem::path& archive);

  bool empty() const { return mounts_.empty(); }
  // The archives addGameDir left out, each error naming the archive (and entry).
  const std::vector<Diagnostic>& skipped() const { return skipped_; }
  // The bytes of `name` ("gfx/palette.lmp") from the first mount that has it; case-insensitive
  // in archives. Names that climb out of the game ("../x", "/etc/x") are never found.
  std::optional<std::vector<uint8_t>> read(std::string_view name) const;
  // The file on disk read(name) takes its bytes from: the loose file, or the archive holding it.
  std::optional<std::filesystem::path> fileHolding(std::string_view name) const;
  // How messages name the file read(name) reads: "/q/id1/pak0.pak:gfx/palette.lmp" or the loose path.
  std::optional<std::string> describe(std::string_view name) const;
  // Names under `folder` ending in `suffix` (case-insensitive), from every mount, deduplicated.
  std::vector<std::string> list(std::string_view folder, std::string_view suffix) const;
  // The mounts in search order, for messages: folders end in '/'.
  std::vector<std::string> describeMounts() const;

private:
  struct Mount {
    std::filesystem::path dir;        // a loose folder, or
    std::unique_ptr<Archive> archive; // an archive
  };
  const Mount* mountHolding(std::string_view name, std::filesystem::path* looseFile) const;

  std::vector<Mount> mounts_; // searched front to back
  std::vector<Diagnostic> skipped_;
};

// True when `name` is a relative path that stays inside the game folder.
bool staysInTheGame(std::string_view name);

} // namespace bt::game
