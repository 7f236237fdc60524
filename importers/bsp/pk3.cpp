#include "importers/bsp/pk3.h"
#include "scene/names.h"

#include "scene/diagnostics.h"

#include <fmt/format.h>
#include <zip.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <set>

namespace bt::bsp {

namespace {
bool endsWith(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}
} // namespace

std::optional<ArchivePath> splitArchivePath(const std::string& path) {
  const std::string lower = lowercase(path);
  for (const char* ext : {".pk3:", ".zip:"}) {
    const size_t at = lower.find(ext);
    if (at != std::string::npos) {
      const size_t split = at + 4;
      return ArchivePath{path.substr(0, split), path.substr(split + 1)};
    }
  }
  return std::nullopt;
}

struct Pk3Archive::Handle {
  zip_t* zip = nullptr;
  ~Handle() {
    if (zip) zip_discard(zip); // read-only: nothing to write back
  }
};

Pk3Archive::Pk3Archive(const std::filesystem::path& path) : path_(path), handle_(std::make_unique<Handle>()) {
  int error = 0;
  handle_->zip = zip_open(path.string().c_str(), ZIP_RDONLY, &error);
  if (!handle_->zip) {
    zip_error_t ze;
    zip_error_init_with_code(&ze, error);
    const std::string message = zip_error_strerror(&ze);
    zip_error_fini(&ze);
    throw ImportError(Diagnostic{Severity::Error, path.string(), 0, 0, "cannot open archive: " + message});
  }
}

Pk3Archive::~Pk3Archive() = default;
Pk3Archive::Pk3Archive(Pk3Archive&&) noexcept = default;
Pk3Archive& Pk3Archive::operator=(Pk3Archive&&) noexcept = default;

std::vector<std::string> Pk3Archive::names() const {
  std::vector<std::string> out;
  const zip_int64_t count = zip_get_num_entries(handle_->zip, 0);
  for (zip_int64_t i = 0; i < count; ++i)
    if (const char* name = zip_get_name(handle_->zip, static_cast<zip_uint64_t>(i), 0)) out.emplace_back(name);
  return out;
}

bool Pk3Archive::contains(std::string_view name) const {
  return zip_name_locate(handle_->zip, std::string(name).c_str(), ZIP_FL_NOCASE) >= 0;
}

std::optional<std::vector<uint8_t>> Pk3Archive::read(std::string_view name, uint64_t maxBytes) const {
  const std::string entryName(name);
  const zip_int64_t index = zip_name_locate(handle_->zip, entryName.c_str(), ZIP_FL_NOCASE);
  if (index < 0) return std::nullopt;
  const std::string where = path_.string() + ":" + entryName;
  zip_stat_t st;
  zip_stat_init(&st);
  if (zip_stat_index(handle_->zip, static_cast<zip_uint64_t>(index), 0, &st) != 0 || !(st.valid & ZIP_STAT_SIZE))
    throw ImportError(Diagnostic{Severity::Error, where, 0, 0, "cannot read the archive entry's size"});
  if (st.size > maxBytes)
    throw ImportError(Diagnostic{Severity::Error, where, 0, 0,
                                 fmt::format("entry is {} bytes, more than the {} allowed", st.size, maxBytes)});
  zip_file_t* file = zip_fopen_index(handle_->zip, static_cast<zip_uint64_t>(index), 0);
  if (!file)
    throw ImportError(Diagnostic{Severity::Error, where, 0, 0,
                                 std::string("cannot open entry: ") + zip_strerror(handle_->zip)});
  std::vector<uint8_t> bytes(static_cast<size_t>(st.size));
  const zip_int64_t got = bytes.empty() ? 0 : zip_fread(file, bytes.data(), bytes.size());
  const std::string error = got < 0 ? zip_file_strerror(file) : "";
  zip_fclose(file);
  if (got < 0 || static_cast<uint64_t>(got) != st.size)
    throw ImportError(Diagnostic{Severity::Error, where, 0, 0,
                                 fmt::format("corrupt entry: read {} of {} bytes {}", got, st.size, error)});
  return bytes;
}

void GameFiles::addGameDir(const std::filesystem::path& dir) {
  std::error_code ec;
  dirs_.push_back(dir);
  std::vector<std::filesystem::path> paks;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
    if (entry.is_regular_file(ec) && lowercase(entry.path().extension().string()) == ".pk3") paks.push_back(entry.path());
  std::sort(paks.begin(), paks.end());
  for (const auto& p : paks) addArchive(p);
}

void GameFiles::addArchive(const std::filesystem::path& archive) {
  for (const Pk3Archive& a : archives_)
    if (a.path() == archive) return;
  archives_.emplace_back(archive);
}

// Names come from the level and its shader scripts: never let them climb out of the game.
static bool staysInTheGame(std::string_view name) {
  const std::filesystem::path relative{std::string(name)};
  if (relative.is_absolute()) return false;
  for (const auto& part : relative)
    if (part == "..") return false;
  return true;
}

std::optional<std::vector<uint8_t>> GameFiles::read(std::string_view name) const {
  if (!staysInTheGame(name)) return std::nullopt;
  for (const auto& dir : dirs_) {
    const std::filesystem::path p = dir / std::filesystem::path(std::string(name));
    std::error_code ec;
    if (std::filesystem::is_regular_file(p, ec)) {
      std::ifstream in(p, std::ios::binary);
      return std::vector<uint8_t>{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }
  }
  for (auto it = archives_.rbegin(); it != archives_.rend(); ++it)
    if (auto bytes = it->read(name)) return bytes;
  return std::nullopt;
}

std::optional<std::filesystem::path> GameFiles::fileHolding(std::string_view name) const {
  // The same search as read(), without reading.
  if (!staysInTheGame(name)) return std::nullopt;
  const std::filesystem::path relative{std::string(name)};
  for (const auto& dir : dirs_) {
    const std::filesystem::path p = dir / relative;
    std::error_code ec;
    if (std::filesystem::is_regular_file(p, ec)) return p;
  }
  for (auto it = archives_.rbegin(); it != archives_.rend(); ++it)
    if (it->contains(name)) return it->path();
  return std::nullopt;
}

std::vector<std::string> GameFiles::list(std::string_view folder, std::string_view suffix) const {
  const std::string prefix = lowercase(folder) + "/";
  const std::string lowerSuffix = lowercase(suffix);
  std::set<std::string> seen;
  std::vector<std::string> out;
  auto consider = [&](const std::string& name) {
    const std::string lower = lowercase(name);
    if (lower.rfind(prefix, 0) == 0 && endsWith(lower, lowerSuffix) && seen.insert(lower).second) out.push_back(name);
  };
  for (const auto& dir : dirs_) {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir / std::string(folder), ec))
      consider(std::string(folder) + "/" + entry.path().filename().string());
  }
  for (const Pk3Archive& a : archives_)
    for (const std::string& name : a.names()) consider(name);
  std::sort(out.begin(), out.end());
  return out;
}

} // namespace bt::bsp
