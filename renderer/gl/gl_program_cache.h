// An on-disk cache of linked program binaries (glGetProgramBinary / glProgramBinary), so that a
// second start skips the driver's shader compiler: on NVIDIA the path tracer takes seconds to
// compile from a cold cache, most of the time to the first image.
//
// Key: a hash of the final source text (after #includes and #defines) and the driver's
// GL_VENDOR, GL_RENDERER and GL_VERSION, so an edited shader or another driver never loads a
// stale binary. Directory: $XDG_CACHE_HOME/brushtrace, else ~/.cache/brushtrace. Disabled with
// BT_SHADER_CACHE=0 (or off). Files are written under a temporary name and renamed, so a reader
// never sees half a file; a file that is unreadable, corrupt or that the driver rejects is
// ignored and the program compiled from source (and the file replaced).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace bt::gl {

// A binding point of a linked program, as the source's layout(binding = N) set it. Stored
// with the binary and applied again after glProgramBinary: the GL spec says the binary keeps
// them, but on NVIDIA's 580 driver programs loaded from a binary read and wrote through
// the wrong units and faulted, which is what lost bindings look like.
struct ProgramBindingPoint {
  enum Kind : int32_t { Uniform = 0, StorageBlock = 1, UniformBlock = 2 };
  int32_t kind = Uniform;
  int32_t index = 0;   // uniform location, or block index
  int32_t binding = 0; // texture/image unit, or buffer binding point
  bool operator==(const ProgramBindingPoint&) const = default;
};

struct ProgramBinary {
  uint32_t format = 0; // one of GL_PROGRAM_BINARY_FORMATS
  std::vector<uint8_t> data;
  std::vector<ProgramBindingPoint> bindings;
};

class ProgramCache {
public:
  ProgramCache() = default; // disabled
  explicit ProgramCache(std::filesystem::path directory) : directory_(std::move(directory)) {}
  // The user's cache directory, or disabled by BT_SHADER_CACHE=0/off or without a home. Off by
  // default on NVIDIA (`glVendor`), whose driver keeps its own shader cache (so warm starts are
  // fast already) and where loaded binaries were seen to fault; BT_SHADER_CACHE=1/on forces it.
  static ProgramCache fromEnvironment(std::string_view glVendor = {});

  bool enabled() const { return !directory_.empty(); }
  const std::filesystem::path& directory() const { return directory_; }

  // The file of a program: `name` (for people reading the directory) and the key's hash.
  std::filesystem::path fileFor(std::string_view name, std::string_view key) const;
  // nullopt when there is no file or it is not a well-formed entry for exactly this key.
  std::optional<ProgramBinary> load(std::string_view name, std::string_view key) const;
  // Best effort: a cache that cannot be written only costs the next start a compile.
  void store(std::string_view name, std::string_view key, const ProgramBinary& binary) const;

private:
  std::filesystem::path directory_;
};

// The cache key of a program: its source text and the driver that compiles it.
std::string programCacheKey(std::string_view source, std::string_view vendor, std::string_view renderer, std::string_view version);

} // namespace bt::gl
