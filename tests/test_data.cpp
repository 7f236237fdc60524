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

std::filesystem::path sourceDir() { return BRUSHTRACE_SOURCE_DIR; }
std::filesystem::path binaryDir() { return BRUSHTRACE_BINARY_DIR; }
std::filesystem::path mapsDir() { return sourceDir() / "maps"; }

} // namespace bt::test
