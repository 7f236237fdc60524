#include "importers/game/archive.h"

#include "importers/bsp/pk3.h"
#include "quake/binary_reader.h"
#include "scene/diagnostics.h"
#include "scene/names.h"

#include <fmt/format.h>

#include <fstream>

namespace bt::game {

namespace {
constexpr size_t kHeaderSize = 12; // "PACK", directory offset, directory length
constexpr size_t kEntrySize = 64;  // name[56], offset, size
constexpr size_t kNameSize = 56;
// Quake's own limit is 2048 files (MAX_FILES_IN_PACK); Quake 2 mods ship bigger paks. Bounded so
// that a corrupt length cannot make us allocate gigabytes for the directory.
constexpr uint64_t kMaxEntries = 1u << 20;

[[noreturn]] void fail(const std::filesystem::path& archive, std::string entry, std::string message) {
  const std::string where = entry.empty() ? archive.string() : archive.string() + ":" + entry;
  throw ImportError(Diagnostic{Severity::Error, where, 0, 0, std::move(message)});
}

std::vector<uint8_t> readRange(const std::filesystem::path& path, uint64_t offset, uint64_t size) {
  std::ifstream in(path, std::ios::binary);
  std::vector<uint8_t> bytes(size);
  if (in && in.seekg(static_cast<std::streamoff>(offset)) && size > 0)
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size));
  if (!in || static_cast<uint64_t>(in.gcount()) != size) bytes.clear();
  return bytes;
}
} // namespace

PakArchive::PakArchive(std::filesystem::path path) : path_(std::move(path)) {
  std::error_code ec;
  const uint64_t fileSize = std::filesystem::file_size(path_, ec);
  if (ec) fail(path_, {}, "cannot open archive: " + ec.message());
  const std::vector<uint8_t> header = fileSize >= kHeaderSize ? readRange(path_, 0, kHeaderSize) : std::vector<uint8_t>{};
  readDirectory(header, fileSize, nullptr);
}

PakArchive::PakArchive(std::filesystem::path path, std::vector<uint8_t> bytes)
    : path_(std::move(path)), bytes_(std::move(bytes)), inMemory_(true) {
  const std::span<const uint8_t> all(bytes_);
  readDirectory(all.first(std::min(all.size(), kHeaderSize)), bytes_.size(), &bytes_);
}

void PakArchive::readDirectory(std::span<const uint8_t> header, uint64_t fileSize, const std::vector<uint8_t>* whole) {
  if (header.size() < kHeaderSize)
    fail(path_, {}, fmt::format("truncated archive: {} bytes, a .pak header alone has {}", fileSize, kHeaderSize));
  if (std::string_view(reinterpret_cast<const char*>(header.data()), 4) != "PACK")
    fail(path_, {}, "not a .pak archive (no PACK signature)");
  const uint64_t dirOffset = quake::readU32(header, 4), dirLength = quake::readU32(header, 8);
  if (dirLength % kEntrySize != 0 || dirLength / kEntrySize > kMaxEntries)
    fail(path_, {}, fmt::format("corrupt directory: length {} is not a whole number of {}-byte entries", dirLength, kEntrySize));
  if (dirOffset > fileSize || dirLength > fileSize - dirOffset)
    fail(path_, {}, fmt::format("truncated archive: the directory ends at byte {} of a {}-byte file", dirOffset + dirLength, fileSize));
  const std::vector<uint8_t> dir = whole ? std::vector<uint8_t>(whole->begin() + static_cast<ptrdiff_t>(dirOffset),
                                                                whole->begin() + static_cast<ptrdiff_t>(dirOffset + dirLength))
                                         : readRange(path_, dirOffset, dirLength);
  if (dir.size() != dirLength) fail(path_, {}, "cannot read the directory");
  for (size_t at = 0; at < dir.size(); at += kEntrySize) {
    Entry entry{quake::readName(dir, at, kNameSize), quake::readU32(dir, at + 56), quake::readU32(dir, at + 60)};
    if (uint64_t{entry.offset} + entry.size > fileSize)
      fail(path_, entry.name,
           fmt::format("directory entry {} lies about its size: bytes {}..{} of a {}-byte file", at / kEntrySize, entry.offset,
                       uint64_t{entry.offset} + entry.size, fileSize));
    entries_.push_back(std::move(entry));
  }
}

std::vector<std::string> PakArchive::names() const {
  std::vector<std::string> out;
  for (const Entry& e : entries_) out.push_back(e.name);
  return out;
}

const PakArchive::Entry* PakArchive::find(std::string_view name) const {
  // Quake takes the first entry of a name; a pak has no duplicates in practice.
  for (const Entry& e : entries_)
    if (equalsIgnoreCase(e.name, name)) return &e;
  return nullptr;
}

std::optional<std::vector<uint8_t>> PakArchive::read(std::string_view name) const {
  const Entry* entry = find(name);
  if (!entry) return std::nullopt;
  if (inMemory_) return std::vector<uint8_t>(bytes_.begin() + entry->offset, bytes_.begin() + entry->offset + entry->size);
  std::vector<uint8_t> bytes = readRange(path_, entry->offset, entry->size);
  if (bytes.size() != entry->size) fail(path_, entry->name, "cannot read the entry (the archive changed or is unreadable)");
  return bytes;
}

bool isArchiveName(const std::filesystem::path& path) {
  const std::string ext = lowercase(path.extension().string());
  return ext == ".pak" || ext == ".pk3" || ext == ".zip";
}

std::unique_ptr<Archive> openArchive(const std::filesystem::path& path) {
  const std::string ext = lowercase(path.extension().string());
  if (ext == ".pak") return std::make_unique<PakArchive>(path);
  if (ext == ".pk3" || ext == ".zip") return std::make_unique<bsp::Pk3Archive>(path);
  return nullptr;
}

std::optional<ArchivePath> splitArchivePath(const std::string& path) {
  const std::string lower = lowercase(path);
  for (const char* ext : {".pk3:", ".pak:", ".zip:"}) {
    const size_t at = lower.find(ext);
    if (at != std::string::npos) {
      const size_t split = at + 4;
      return ArchivePath{path.substr(0, split), path.substr(split + 1)};
    }
  }
  return std::nullopt;
}

} // namespace bt::game
