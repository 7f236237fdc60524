// The batch's merged report.json and its index.html contact sheet (README, "brushtrace batch").
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace bt::app::batch {

// Reads every levels/*.json under `outDir` (any shard's), writes report.json and index.html
// there (each to a temporary name and renamed) and returns the report. The results are in
// level-path order, so every way of slicing a batch merges to the same report.
nlohmann::json mergeResults(const std::string& outDir);

// The contact sheet: self-contained HTML (inline style, relative image paths, no script), so it
// opens from file:// with no server. Failed levels come first, with their messages.
std::string contactSheet(const nlohmann::json& report);

} // namespace bt::app::batch
