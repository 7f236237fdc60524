#include "renderer/gl/gl_program_cache.h"

#include <fmt/format.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <system_error>

namespace bt::gl {

namespace {

// File layout: magic with the format version, the GL binary format, the key's length and text,
// the binding points' count and values, the binary's length and bytes (host byte order: the
// file never leaves this machine).
constexpr char kMagic[8] = {'B', 'T', 'P', 'R', 'O', 'G', '0', '2'};

uint64_t fnv1a64(std::string_view text) {
  uint64_t h = 14695981039346656037ull;
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  return h;
}

template <typename T> void put(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

template <typename T> bool get(std::string_view& in, T& value) {
  if (in.size() < sizeof value) return false;
  std::memcpy(&value, in.data(), sizeof value);
  in.remove_prefix(sizeof value);
  return true;
}

} // namespace

std::string programCacheKey(std::string_view source, std::string_view vendor, std::string_view renderer, std::string_view version) {
  // The whole text, not just its hash, goes into the file: a hash collision then reads as a
  // mismatch instead of loading another program's binary.
  return fmt::format("{}\n{}\n{}\n{}", vendor, renderer, version, source);
}

ProgramCache ProgramCache::fromEnvironment(std::string_view glVendor) {
  const char* env = std::getenv("BT_SHADER_CACHE");
  const std::string_view setting = env ? env : "";
  if (setting == "0" || setting == "off") return {};
  const bool forced = setting == "1" || setting == "on";
  if (!forced && glVendor.find("NVIDIA") != std::string_view::npos) return {};
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return ProgramCache(std::filesystem::path(xdg) / "brushtrace");
  if (const char* home = std::getenv("HOME"); home && *home) return ProgramCache(std::filesystem::path(home) / ".cache" / "brushtrace");
  return {};
}

std::filesystem::path ProgramCache::fileFor(std::string_view name, std::string_view key) const {
  return directory_ / fmt::format("{}-{:016x}.glbin", name, fnv1a64(key));
}

std::optional<ProgramBinary> ProgramCache::load(std::string_view name, std::string_view key) const {
  if (!enabled()) return std::nullopt;
  std::ifstream in(fileFor(name, key), std::ios::binary);
  if (!in) return std::nullopt;
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string_view rest = bytes;
  ProgramBinary binary;
  uint64_t keyLength = 0, dataLength = 0;
  if (rest.size() < sizeof kMagic || std::memcmp(rest.data(), kMagic, sizeof kMagic) != 0) return std::nullopt;
  rest.remove_prefix(sizeof kMagic);
  if (!get(rest, binary.format) || !get(rest, keyLength) || keyLength > rest.size()) return std::nullopt;
  if (rest.substr(0, keyLength) != key) return std::nullopt;
  rest.remove_prefix(keyLength);
  uint64_t bindingCount = 0;
  if (!get(rest, bindingCount) || bindingCount > rest.size() / sizeof(ProgramBindingPoint)) return std::nullopt;
  binary.bindings.resize(bindingCount);
  for (ProgramBindingPoint& b : binary.bindings)
    if (!get(rest, b.kind) || !get(rest, b.index) || !get(rest, b.binding)) return std::nullopt;
  if (!get(rest, dataLength) || dataLength != rest.size() || dataLength == 0) return std::nullopt;
  binary.data.assign(rest.begin(), rest.end());
  return binary;
}

void ProgramCache::store(std::string_view name, std::string_view key, const ProgramBinary& binary) const {
  if (!enabled() || binary.data.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  if (ec) return;
  std::string out(kMagic, sizeof kMagic);
  put(out, binary.format);
  put(out, static_cast<uint64_t>(key.size()));
  out.append(key);
  put(out, static_cast<uint64_t>(binary.bindings.size()));
  for (const ProgramBindingPoint& b : binary.bindings) {
    put(out, b.kind);
    put(out, b.index);
    put(out, b.binding);
  }
  put(out, static_cast<uint64_t>(binary.data.size()));
  out.append(reinterpret_cast<const char*>(binary.data.data()), binary.data.size());

  const std::filesystem::path file = fileFor(name, key);
  // A name of our own next to the target: two processes storing at once each rename a whole file.
  const std::filesystem::path temporary = file.string() + fmt::format(".tmp{:08x}", std::random_device{}());
  {
    std::ofstream tmp(temporary, std::ios::binary | std::ios::trunc);
    if (!tmp.write(out.data(), static_cast<std::streamsize>(out.size())) || !tmp.flush()) {
      tmp.close();
      std::filesystem::remove(temporary, ec);
      return;
    }
  }
  std::filesystem::rename(temporary, file, ec);
  if (ec) std::filesystem::remove(temporary, ec);
}

} // namespace bt::gl
