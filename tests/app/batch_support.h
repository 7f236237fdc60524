// Helpers of the batch command's tests (batch_command_test.cpp, slurm_batch_test.cpp).
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace bt::test {

std::string readText(const std::filesystem::path& p);
nlohmann::json readJson(const std::filesystem::path& p);
void writeText(const std::filesystem::path& p, const std::string& text);
// The report without its timings (every "seconds" key): what two runs of one batch share.
nlohmann::json withoutTimings(nlohmann::json j);
// Files under `dir` whose name says they were left half-written (a temporary name).
std::vector<std::filesystem::path> partialFiles(const std::filesystem::path& dir);
// A fresh temporary folder named after the test.
std::filesystem::path freshTempDir(const std::string& name);

} // namespace bt::test
