// Quake 3 .pk3 archives (zip files, read with libzip) and the "archive.pk3:inner/path" names
// that brushtrace accepts wherever a level path goes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace bt::bsp {

// "dir/pak.pk3:maps/x.bsp" → {"dir/pak.pk3", "maps/x.bsp"}; nullopt for a plain path.
struct ArchivePath {
  std::string archive;
  std::string entry;
};
std::optional<ArchivePath> splitArchivePath(const std::string& path);

class Pk3Archive {
public:
  // Throws ImportError when the file cannot be opened as a zip archive.
  explicit Pk3Archive(const std::filesystem::path& path);
  ~Pk3Archive();
  Pk3Archive(Pk3Archive&&) noexcept;
  Pk3Archive& operator=(Pk3Archive&&) noexcept;

  const std::filesystem::path& path() const { return path_; }
  // Every file name in the archive, as stored.
  std::vector<std::string> names() const;
  // The bytes of `name` (case-insensitive, as Quake 3 looks files up), nullopt when absent.
  // Throws ImportError when the entry is corrupt or larger than `maxBytes`.
  std::optional<std::vector<uint8_t>> read(std::string_view name, uint64_t maxBytes = uint64_t{1} << 30) const;
  bool contains(std::string_view name) const;

private:
  struct Handle;
  std::filesystem::path path_;
  std::unique_ptr<Handle> handle_;
};

// The files a Quake 3 game directory offers: loose files in the directory itself, then its
// .pk3 archives, later ones (by name) overriding earlier ones as the engine does.
class GameFiles {
public:
  // Mounts every .pk3 in `dir` (and the loose files under it).
  void addGameDir(const std::filesystem::path& dir);
  void addArchive(const std::filesystem::path& archive);

  std::optional<std::vector<uint8_t>> read(std::string_view name) const;
  // The file on disk that read(name) takes its bytes from: the loose file, or the .pk3 holding
  // it; std::nullopt when there is none.
  std::optional<std::filesystem::path> fileHolding(std::string_view name) const;
  // Names under `folder` ending in `suffix` (case-insensitive), from every source, deduplicated.
  std::vector<std::string> list(std::string_view folder, std::string_view suffix) const;

private:
  std::vector<std::filesystem::path> dirs_;
  std::vector<Pk3Archive> archives_; // searched last to first
};

} // namespace bt::bsp
