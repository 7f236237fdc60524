// Files of a batch's output folder: content hashes and whole-file writes.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace bt::app::batch {

// SHA-256 of bytes / of a file's bytes (OpenSSL), as lowercase hex. The file form throws
// std::runtime_error naming a file it cannot read.
std::string sha256Hex(const std::string& bytes);
std::string sha256File(const std::string& path);

// Writes JSON through a temporary file beside `path` and a rename: a reader, or a batch
// restarted after a kill, never sees half a result.
void writeJsonAtomically(const std::string& path, const nlohmann::json& json);
// The file's JSON, or nullopt when it is missing or not JSON (a result from an older run).
std::optional<nlohmann::json> readJsonFile(const std::string& path);

} // namespace bt::app::batch
