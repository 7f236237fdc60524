#include "app/commands.h"

#include <filesystem>
#include <stdexcept>
#include <vector>

namespace bt::app {

// maps/start.map in the current directory, else where this executable's data is: the source
// tree for the build tree's executable, PREFIX/share/brushtrace for an installed one
// (PREFIX/bin/brushtrace). An installed executable never looks in the source tree it was built
// from, so that an install that lacks its map fails here rather than pass on this machine.
std::string defaultMapPath() {
  namespace fs = std::filesystem;
  std::vector<fs::path> candidates{fs::current_path() / "maps" / "start.map"};
  std::error_code ec;
  const fs::path exeDir = fs::read_symlink("/proc/self/exe", ec).parent_path();
  if (!ec && fs::equivalent(exeDir, BRUSHTRACE_BINARY_DIR, ec))
    candidates.push_back(fs::path(BRUSHTRACE_SOURCE_DIR) / "maps" / "start.map");
  else if (!exeDir.empty())
    candidates.push_back((exeDir / BRUSHTRACE_DATA_FROM_BINDIR / "maps" / "start.map").lexically_normal());
  for (const fs::path& p : candidates)
    if (fs::is_regular_file(p, ec)) return p.string();
  std::string looked;
  for (const fs::path& p : candidates) looked += (looked.empty() ? "" : ", ") + p.string();
  throw std::runtime_error("no MAP given and the default map is not where it was looked for: " + looked);
}

} // namespace bt::app
