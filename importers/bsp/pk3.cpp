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
    throw ImportError(
        Diagnostic{Severity::Error, where, 0, 0, fmt::format("entry is {} bytes, more than the {} allowed", st.size, maxBytes)});
  zip_file_t* file = zip_fopen_index(handle_->zip, static_cast<zip_uint64_t>(index), 0);
  if (!file) throw ImportError(Diagnostic{Severity::Error, where, 0, 0, std::string("cannot open entry: ") + zip_strerror(handle_->zip)});
  std::vector<uint8_t> bytes(static_cast<size_t>(st.size));
  const zip_int64_t got = bytes.empty() ? 0 : zip_fread(file, bytes.data(), bytes.size());
  const std::string error = got < 0 ? zip_file_strerror(file) : "";
  zip_fclose(file);
  if (got < 0 || static_cast<uint64_t>(got) != st.size)
    throw ImportError(Diagnostic{Severity::Error, where, 0, 0, fmt::format("corrupt entry: read {} of {} bytes {}", got, st.size, error)});
  return bytes;
}

} // namespace bt::bsp
