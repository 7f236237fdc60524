// Runs a manifest's levels, each in a child process, into an output folder (README, "brushtrace batch").
#pragma once

#include "app/batch/batch_manifest.h"

#include <string>

namespace bt::app::batch {

struct RunOptions {
  std::string outDir;
  int shard = 1; // this run's slice, `shard` of `shards` (1-based)
  int shards = 1;
};

// Runs every level of the slice whose result is missing or out of date, one child process at a
// time, and prints a line per level and a `[ 42%]` line. Returns the number of levels whose
// result says failed (skipped ones included). Throws when the output folder cannot be written.
// Stops early, returning -1, when the process is asked to stop (SIGTERM, SIGINT).
int runBatch(const Manifest& manifest, const RunOptions& options);

} // namespace bt::app::batch
