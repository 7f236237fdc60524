// Game archives: Quake's .pak (read here: a 12-byte header and a directory of 64-byte entries)
// and Quake 3's .pk3 (zip, read with libzip: importers/bsp/pk3.h), behind one interface so that
// the game file system (file_system.h) mounts either.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace bt::game {

class Archive {
public:
  virtual ~Archive() = default;
  virtual const std::filesystem::path& path() const = 0;
  // Every file name in the archive, as stored ('/' separated).
  virtual std::vector<std::string> names() const = 0;
  virtual bool contains(std::string_view name) const = 0;
  // The bytes of `name` (case-insensitive, as the engines look files up), nullopt when absent.
  // Throws ImportError naming archive and entry when the entry cannot be read.
  virtual std::optional<std::vector<uint8_t>> read(std::string_view name) const = 0;
};

// A Quake / Quake 2 / Hexen II / Half-Life .pak. The directory is read and checked on open;
// entries are read from the file when asked for, so a 20 MB pak0.pak costs only its directory.
class PakArchive final : public Archive {
public:
  struct Entry {
    std::string name; // up to 56 characters
    uint32_t offset = 0;
    uint32_t size = 0;
  };
  // Throws ImportError naming the file (and the entry) when it is not a PACK file, is truncated,
  // or has a directory entry that lies outside the file.
  explicit PakArchive(std::filesystem::path path);
  // For bytes already in memory (the fuzz harness, tests); `path` only names it in messages.
  PakArchive(std::filesystem::path path, std::vector<uint8_t> bytes);

  const std::filesystem::path& path() const override { return path_; }
  std::vector<std::string> names() const override;
  bool contains(std::string_view name) const override { return find(name) != nullptr; }
  std::optional<std::vector<uint8_t>> read(std::string_view name) const override;
  const std::vector<Entry>& entries() const { return entries_; }

private:
  void readDirectory(std::span<const uint8_t> header, uint64_t fileSize, const std::vector<uint8_t>* whole);
  const Entry* find(std::string_view name) const;

  std::filesystem::path path_;
  std::vector<Entry> entries_;
  std::vector<uint8_t> bytes_; // only for archives given as bytes
  bool inMemory_ = false;
};

// .pak or .pk3/.zip by extension ("pak0.pak", "pak0.pk3"); nullptr for anything else.
std::unique_ptr<Archive> openArchive(const std::filesystem::path& path);
bool isArchiveName(const std::filesystem::path& path);

// "dir/pak0.pak:maps/e1m1.bsp" → {"dir/pak0.pak", "maps/e1m1.bsp"}; nullopt for a plain path.
struct ArchivePath {
  std::string archive;
  std::string entry;
};
std::optional<ArchivePath> splitArchivePath(const std::string& path);

} // namespace bt::game
