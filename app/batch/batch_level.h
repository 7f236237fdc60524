// One level's jobs, run inside the child process the batch starts for it (batch_runner.h).
#pragma once

#include "app/batch/batch_manifest.h"

#include <nlohmann/json.hpp>

#include <string>

namespace bt::app::batch {

// Runs the import check, the same-dialect round trip and the renders of `level`, writing images
// under `workDir`/images/ (named as `imagePrefix` + file name, the path the report will show
// once the runner has moved them), and returns the level's result (README, "Per-level results").
// A job that fails is recorded in the result's "failures" and the next job still runs.
nlohmann::json runLevelJobs(const Level& level, const Jobs& jobs, const std::string& workDir, const std::string& imagePrefix);

// The result of a level whose child process did not finish (a crash, a timeout): `job` failed
// with `message`, and the level file is its only known input.
nlohmann::json failedLevel(const Level& level, const std::string& job, const std::string& message);

// The files a result was made from, with their hashes, and the hash over them and the job:
// a level is skipped when a result's "input_hash" equals inputHash() of its recorded inputs now.
nlohmann::json hashInputs(const std::vector<std::string>& files);
std::string inputHash(const nlohmann::json& inputs, const std::string& jobHash);

} // namespace bt::app::batch
