#include "app/batch/batch_report.h"

#include "app/batch/batch_files.h"
#include "importers/map/map_writer.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace bt::app::batch {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string escapeHtml(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
    case '&': out += "&amp;"; break;
    case '<': out += "&lt;"; break;
    case '>': out += "&gt;"; break;
    case '"': out += "&quot;"; break;
    default: out += c;
    }
  }
  return out;
}

json summaryOf(const json& levels) {
  size_t failed = 0, images = 0;
  double seconds = 0.0;
  for (const json& level : levels) {
    failed += level.value("status", "") != "ok";
    images += level.value("renders", json::array()).size();
    seconds += level.value("seconds", 0.0);
  }
  return {{"levels", levels.size()},
          {"ok", levels.size() - failed},
          {"failed", failed},
          {"images", images},
          {"seconds", std::round(seconds * 1000.0) / 1000.0}};
}

// The figures under a thumbnail: what info and the round trip found, and the times.
std::string figures(const json& level) {
  std::string text;
  if (level.contains("import")) {
    const json& info = level["import"]["info"];
    size_t missing = 0;
    for (const json& t : info["textures"]) missing += !t.value("found", false);
    text += fmt::format("{} &middot; {} brushes &middot; {} faces<br>{} textures, {} missing &middot; {} problems<br>",
                        escapeHtml(info.value("dialect", "")), info.value("brushes", 0), info.value("faces", 0), info["textures"].size(),
                        missing, info["problems"].size());
  }
  if (level.contains("roundtrip"))
    text += level["roundtrip"].value("lossless", false) ? "round trip lossless<br>" : "round trip CHANGED<br>";
  text += fmt::format("{:.2f} s", level.value("seconds", 0.0));
  return text;
}

std::string card(const json& level) {
  const bool ok = level.value("status", "") == "ok";
  std::string thumbs;
  for (const json& r : level.value("renders", json::array()))
    thumbs +=
        fmt::format("<img src=\"{}\" alt=\"{}\" title=\"{} {} {}\">", escapeHtml(r.value("image", "")), escapeHtml(r.value("source", "")),
                    escapeHtml(r.value("camera", "")), escapeHtml(r.value("lighting", "")), escapeHtml(r.value("aov", "")));
  if (thumbs.empty()) thumbs = "<div class=\"noimage\">no image</div>";
  return fmt::format(
      "<div class=\"card {}\">{}<div class=\"name\" title=\"{}\">{}</div><div class=\"status\">{}</div><div class=\"fig\">{}</div></div>\n",
      ok ? "ok" : "failed", thumbs, escapeHtml(level.value("level", "")),
      escapeHtml(fs::path(level.value("level", "")).filename().string()), ok ? "ok" : "FAILED", figures(level));
}

const char* const kStyle = R"(body{font:14px sans-serif;margin:1em;background:#222;color:#ddd}
h1,h2{font-weight:normal}table{border-collapse:collapse}td{border-top:1px solid #555;padding:2px 8px;vertical-align:top}
.grid{display:flex;flex-wrap:wrap;gap:8px}.card{width:210px;background:#333;padding:4px;border-left:4px solid #4a4}
.card.failed{border-left-color:#d33}.card img{width:200px;image-rendering:pixelated;display:block;margin-bottom:2px}
.noimage{width:200px;height:112px;background:#111;color:#888;text-align:center;line-height:112px}
.name{font-weight:bold;overflow:hidden;text-overflow:ellipsis;white-space:nowrap}.failed .status{color:#f66}.fig{font-size:12px;color:#aaa}
#failures td:first-child{color:#f66})";

} // namespace

std::string contactSheet(const json& report) {
  const json& summary = report["summary"];
  std::vector<const json*> levels;
  for (const json& level : report["levels"]) levels.push_back(&level);
  std::stable_partition(levels.begin(), levels.end(), [](const json* l) { return l->value("status", "") != "ok"; });
  std::string failures;
  for (const json* level : levels)
    for (const json& f : level->value("failures", json::array()))
      failures += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td></tr>\n", escapeHtml(level->value("level", "")),
                              escapeHtml(f.value("job", "")), escapeHtml(f.value("message", "")));
  std::string cards;
  for (const json* level : levels) cards += card(*level);
  return fmt::format(
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>brushtrace batch</title><style>{}</style></head><body>\n"
      "<h1>brushtrace batch: {} levels, {} ok, {} failed, {} images, {:.1f} s</h1>\n"
      "<h2>Failures</h2>\n<table id=\"failures\">\n{}</table>\n<h2>Levels</h2>\n<div class=\"grid\">\n{}</div>\n</body></html>\n",
      kStyle, summary.value("levels", 0), summary.value("ok", 0), summary.value("failed", 0), summary.value("images", 0),
      summary.value("seconds", 0.0), failures.empty() ? "<tr><td>none</td></tr>\n" : failures, cards);
}

json mergeResults(const std::string& outDir) {
  const fs::path out = outDir;
  json levels = json::array();
  if (fs::is_directory(out / "levels"))
    for (const auto& entry : fs::directory_iterator(out / "levels")) {
      const std::string name = entry.path().filename().string();
      if (name.starts_with(".") || entry.path().extension() != ".json") continue; // temporary files
      if (auto result = readJsonFile(entry.path().string())) levels.push_back(std::move(*result));
    }
  std::sort(levels.begin(), levels.end(), [](const json& a, const json& b) { return a.value("level", "") < b.value("level", ""); });
  const json report{{"summary", summaryOf(levels)}, {"levels", levels}};
  writeJsonAtomically((out / "report.json").string(), report);
  map::writeFileAtomically((out / "index.html").string(), contactSheet(report));
  return report;
}

} // namespace bt::app::batch
