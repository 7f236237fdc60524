#include "tests/test_data.h"

#include <cstdlib>

namespace bt::test {

std::optional<std::filesystem::path> sharedDir() {
  std::filesystem::path dir = BRUSHTRACE_SHARED_DIR;
  if (const char* env = std::getenv("BRUSHTRACE_SHARED_DIR")) dir = env;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir / "maps", ec)) return std::nullopt;
  return std::filesystem::weakly_canonical(dir, ec);
}

// $BRUSHTRACE_SOURCE_DIR overrides the build's own path for test binaries carried to another
// machine (scripts/gpu-check.sh), where the repository sits elsewhere.
std::filesystem::path sourceDir() {
  if (const char* env = std::getenv("BRUSHTRACE_SOURCE_DIR"); env && *env) return env;
  return BRUSHTRACE_SOURCE_DIR;
}
std::filesystem::path binaryDir() {
  return BRUSHTRACE_BINARY_DIR;
}
std::filesystem::path mapsDir() {
  return sourceDir() / "maps";
}

} // namespace bt::test
