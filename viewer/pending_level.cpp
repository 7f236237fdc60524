#include "viewer/pending_level.h"

#include <system_error>

namespace bt {

std::filesystem::path levelFileOf(const std::string& map) {
  std::error_code ec;
  if (std::filesystem::exists(map, ec)) return map;
  const size_t colon = map.rfind(':');
  return colon == std::string::npos ? std::filesystem::path(map) : std::filesystem::path(map.substr(0, colon));
}

} // namespace bt
