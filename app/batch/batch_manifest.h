// What `brushtrace batch` runs: the levels and, for each, the jobs (README, "brushtrace batch").
#pragma once

#include "app/commands.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace bt::app::batch {

// The renders made of each level: every camera times every lighting mode times every AOV.
struct RenderJob {
  ImageSize size{320, 180};
  int spp = 16;
  double seconds = 0.0; // a time limit per image; 0: spp alone
  std::vector<std::string> lighting{"faithful"};
  std::vector<std::string> aovs{"beauty"};
  int spawnCameras = 0; // further cameras from the level's spawn points, after the default one
  std::string backend = "auto";
  uint32_t seed = 0;
};

struct Jobs {
  bool import = true;
  bool roundTrip = true;
  std::optional<RenderJob> render = RenderJob{};
};

// One level as the importers open it: a path, ARCHIVE:maps/x.bsp, or a name with a game install.
struct Level {
  std::string path;
  ImportOptions import;
  std::string id;       // its results' file names: the path made safe, and a hash of it
  nlohmann::json entry; // the manifest's entry, part of the job hash
};

struct Limits {
  double seconds = 600.0; // per level, all its jobs
  long memoryMb = 8192;   // the child process's address space; 0: no limit
};

struct Manifest {
  std::vector<Level> levels; // in manifest order, globs expanded in name order
  Jobs jobs;
  Limits limits;
};

// Reads a manifest file; relative paths are relative to it. Throws std::runtime_error naming
// the file (and the entry) on bad JSON, an unknown key, a bad value or a glob matching nothing.
Manifest readManifest(const std::string& path);
// `batch LEVEL...`: the default jobs over the levels given (folders: every .map and .bsp under them).
Manifest manifestForLevels(const std::vector<std::string>& paths);

// The jobs as JSON (what the job hash covers, beside the level's own entry).
nlohmann::json toJson(const Jobs& jobs);

// Shard `k` of `n` (1-based): every n-th level from the k-th, so each shard gets the pack's
// mix of small and large levels and the slices depend only on the manifest.
std::vector<Level> shardOf(const std::vector<Level>& levels, int k, int n);

} // namespace bt::app::batch
