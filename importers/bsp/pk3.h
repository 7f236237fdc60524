// Quake 3 .pk3 archives (zip files, read with libzip).
#pragma once

#include "importers/game/archive.h"
#include "importers/game/file_system.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace bt::bsp {

// "dir/pak0.pk3:maps/x.bsp" → {"dir/pak0.pk3", "maps/x.bsp"} (importers/game/archive.h).
using ArchivePath = game::ArchivePath;
using game::splitArchivePath;

class Pk3Archive final : public game::Archive {
public:
  // Throws ImportError when the file cannot be opened as a zip archive.
  explicit Pk3Archive(const std::filesystem::path& path);
  ~Pk3Archive();
  Pk3Archive(Pk3Archive&&) noexcept;
  Pk3Archive& operator=(Pk3Archive&&) noexcept;

  const std::filesystem::path& path() const override { return path_; }
  // Every file name in the archive, as stored.
  std::vector<std::string> names() const override;
  // The bytes of `name` (case-insensitive, as Quake 3 looks files up), nullopt when absent.
  // Throws ImportError when the entry is corrupt or larger than `maxBytes`.
  std::optional<std::vector<uint8_t>> read(std::string_view name, uint64_t maxBytes) const;
  std::optional<std::vector<uint8_t>> read(std::string_view name) const override { return read(name, uint64_t{1} << 30); }
  bool contains(std::string_view name) const override;

private:
  struct Handle;
  std::filesystem::path path_;
  std::unique_ptr<Handle> handle_;
};

// The files a Quake 3 game directory offers: importers/game/file_system.h.
using GameFiles = game::FileSystem;

} // namespace bt::bsp
