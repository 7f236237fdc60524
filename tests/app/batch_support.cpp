#include "tests/app/batch_support.h"

#include <fstream>
#include <iterator>
#include <unistd.h>

namespace bt::test {

namespace fs = std::filesystem;

std::string readText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

nlohmann::json readJson(const fs::path& p) {
  return nlohmann::json::parse(readText(p));
}

void writeText(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

nlohmann::json withoutTimings(nlohmann::json j) {
  if (j.is_object()) {
    j.erase("seconds");
    for (auto& [key, value] : j.items()) value = withoutTimings(value);
  } else if (j.is_array()) {
    for (auto& value : j) value = withoutTimings(value);
  }
  return j;
}

std::vector<fs::path> partialFiles(const fs::path& dir) {
  std::vector<fs::path> found;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.ends_with(".tmp") || name == "tmp" || name.find(".tmp.") != std::string::npos) found.push_back(entry.path());
  }
  return found;
}

fs::path freshTempDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("bt_batch_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

} // namespace bt::test
