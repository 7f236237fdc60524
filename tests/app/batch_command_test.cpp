// brushtrace batch, run as users run it: every shared map's result against the single commands,
// restarts, shards and merges, a level's crash or timeout, usage errors.
#include "tests/app/batch_support.h"
#include "tests/app/run_command.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <openssl/evp.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <set>
#include <filesystem>

namespace {

namespace fs = std::filesystem;
using bt::test::brushtrace;
using bt::test::CommandResult;
using nlohmann::json;

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

std::string sha256(const std::string& bytes) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned size = 0;
  EVP_Digest(bytes.data(), bytes.size(), digest, &size, EVP_sha256(), nullptr);
  std::string hex;
  static constexpr char digits[] = "0123456789abcdef";
  for (unsigned i = 0; i < size; ++i) hex += {digits[digest[i] >> 4], digits[digest[i] & 15]};
  return hex;
}

// The level's import check against `brushtrace info --json`, its round trip against `convert`
// (the same bytes), its image against `render` with the same options (the same PNG bytes, so
// the same pixels) and the camera `render` prints.
void expectSameAsSingleCommands(const json& level, const fs::path& out, const fs::path& scratch) {
  const std::string path = level.at("level");
  SCOPED_TRACE(path);
  const CommandResult info = brushtrace("info --json " + q(path));
  ASSERT_EQ(info.exitCode, 0) << info.err;
  EXPECT_EQ(level.at("import").at("info"), json::parse(info.out));

  const CommandResult convert = brushtrace("convert " + q(path) + " -o " + q(scratch / "rewritten.map"));
  ASSERT_EQ(convert.exitCode, 0) << convert.err;
  const std::string rewritten = bt::test::readText(scratch / "rewritten.map");
  EXPECT_EQ(level.at("roundtrip").at("sha256"), sha256(rewritten));
  EXPECT_EQ(level.at("roundtrip").at("bytes"), rewritten.size());
  EXPECT_TRUE(level.at("roundtrip").at("lossless"));

  const CommandResult render =
      brushtrace("render " + q(path) + " -o " + q(scratch / "single.png") + " --size 64x36 --spp 1 --backend cpu --lighting physical");
  if (render.exitCode != 0) { // a level with nothing to draw: the batch records the same failure
    EXPECT_NE(render.err.find("no face to draw"), std::string::npos) << render.err;
    ASSERT_EQ(level.at("failures").size(), 1u);
    EXPECT_EQ(level["failures"][0].at("job"), "render");
    EXPECT_EQ(level.value("renders", json::array()).size(), 0u);
    return;
  }
  EXPECT_EQ(level.at("status"), "ok");
  ASSERT_EQ(level.at("renders").size(), 1u);
  const json& image = level["renders"][0];
  // The camera line, after the lines on what is drawn (curves, entity models not drawn).
  const size_t cameraAt = render.out.starts_with("camera ") ? 0 : render.out.find("\ncamera ") + 1;
  const std::string cameraLine = render.out.substr(cameraAt, render.out.find('\n', cameraAt) - cameraAt);
  EXPECT_EQ(cameraLine, "camera " + image.at("camera").get<std::string>() + " (" + image.at("source").get<std::string>() + ")");
  const std::string batchPng = bt::test::readText(out / image.at("image").get<std::string>());
  EXPECT_FALSE(batchPng.empty());
  EXPECT_TRUE(batchPng == bt::test::readText(scratch / "single.png")) << "the batch's image differs from render's";
  EXPECT_EQ(image.at("sha256"), sha256(batchPng));
}

// Physical lighting: faithful mode bakes the compiler's luxels before the first sample, 10-30 s
// on the three largest shared maps on a loaded 2-core machine, where physical takes about 1 s.
TEST(BatchCommand, EverySharedMapGivesWhatTheSingleCommandsGive) {
  BT_REQUIRE_SHARED(shared);
  const fs::path dir = bt::test::freshTempDir("shared");
  bt::test::writeText(dir / "manifest.json",
                      json{{"levels", {(shared / "maps").string()}},
                           {"jobs", {{"render", {{"size", "64x36"}, {"spp", 1}, {"backend", "cpu"}, {"lighting", {"physical"}}}}}}}
                          .dump());
  const CommandResult r = brushtrace("batch " + q(dir / "manifest.json") + " -o " + q(dir / "out"));
  const json report = bt::test::readJson(dir / "out" / "report.json");
  const size_t failed = report.at("summary").at("failed");
  EXPECT_EQ(r.exitCode, failed == 0 ? 0 : 1) << r.err;
  size_t maps = 0;
  for (const auto& e : fs::recursive_directory_iterator(shared / "maps")) maps += e.path().extension() == ".map";
  ASSERT_EQ(report.at("levels").size(), maps);
  EXPECT_EQ(report.at("summary").at("levels"), maps);
  // One progress line per level and its percentage, the last at 100 %.
  EXPECT_EQ(size_t(std::count(r.out.begin(), r.out.end(), '\n')), 2 * maps);
  const std::string last =
      "[100%] " + std::to_string(maps) + "/" + std::to_string(maps) + " levels, " + std::to_string(failed) + " failed\n";
  EXPECT_TRUE(r.out.ends_with(last)) << r.out.substr(r.out.size() - 200);
  // Every level against the single commands (702 commands; 2 min 17 s on the loaded 2-core
  // machine, since brushtrace starts in milliseconds). BT_BATCH_TEST_EVERY=N compares every Nth.
  const char* every = std::getenv("BT_BATCH_TEST_EVERY");
  const size_t step = every ? std::max(1, std::atoi(every)) : 1;
  for (size_t i = 0; i < report["levels"].size(); ++i) {
    const json& level = report["levels"][i];
    EXPECT_TRUE(level.contains("import") && level.contains("roundtrip")) << level.at("level");
    if (i % step == 0) expectSameAsSingleCommands(level, dir / "out", dir);
  }
  EXPECT_TRUE(bt::test::partialFiles(dir / "out").empty());
  fs::remove_all(dir);
}

// Two of the repository's small maps: one with a player start, one .map per dialect.
json smallManifest(const fs::path& dir, const std::string& extra = "") {
  for (const char* name : {"standard", "quake2"})
    fs::copy_file(bt::test::mapsDir() / "dialects" / (std::string(name) + ".map"), dir / (std::string(name) + ".map"),
                  fs::copy_options::skip_existing);
  return json::parse(R"({"levels": ["*.map"], "jobs": {"render": {"size": "32x18", "spp": 1, "backend": "cpu", "lighting": ["physical"],
                        "aovs": ["beauty", "albedo"]}})" +
                     extra + "}");
}

std::vector<std::string> statusWords(const std::string& out) {
  std::vector<std::string> words;
  for (size_t at = 0; at < out.size(); at = out.find('\n', at) + 1) {
    if (out[at] != '[') words.push_back(out.substr(at, out.find(' ', at) - at));
    if (out.find('\n', at) == std::string::npos) break;
  }
  return words;
}

TEST(BatchCommand, ARerunSkipsUnchangedLevelsAndRedoesChangedOnes) {
  const fs::path dir = bt::test::freshTempDir("restart");
  bt::test::writeText(dir / "m.json", smallManifest(dir).dump());
  const std::string batch = "batch " + q(dir / "m.json") + " -o " + q(dir / "out");
  const CommandResult first = brushtrace(batch);
  ASSERT_EQ(first.exitCode, 0) << first.err << first.out;
  EXPECT_EQ(statusWords(first.out), (std::vector<std::string>{"ok", "ok"})) << first.out;
  const json report = bt::test::readJson(dir / "out" / "report.json");
  ASSERT_EQ(report.at("levels").size(), 2u);
  EXPECT_EQ(report["levels"][0].at("renders").size(), 2u); // beauty and albedo
  for (const json& level : report["levels"])
    for (const json& image : level["renders"]) EXPECT_TRUE(fs::is_regular_file(dir / "out" / image.at("image").get<std::string>()));

  const CommandResult again = brushtrace(batch);
  EXPECT_EQ(statusWords(again.out), (std::vector<std::string>{"skipped", "skipped"})) << again.out;
  std::ofstream(dir / "quake2.map", std::ios::app) << "// edited\n";
  const CommandResult edited = brushtrace(batch);
  EXPECT_EQ(statusWords(edited.out), (std::vector<std::string>{"ok", "skipped"})) << edited.out; // quake2.map sorts first
  EXPECT_TRUE(bt::test::partialFiles(dir / "out").empty());
  fs::remove_all(dir);
}

TEST(BatchCommand, ShardsMergeToTheReportOfOneRun) {
  const fs::path dir = bt::test::freshTempDir("shards");
  bt::test::writeText(dir / "m.json", smallManifest(dir).dump());
  ASSERT_EQ(brushtrace("batch " + q(dir / "m.json") + " -o " + q(dir / "whole")).exitCode, 0);
  for (const char* shard : {"1/2", "2/2"}) {
    const CommandResult r = brushtrace("batch " + q(dir / "m.json") + " -o " + q(dir / "sharded") + " --shard " + shard);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(statusWords(r.out).size(), 1u) << r.out;
  }
  EXPECT_FALSE(fs::exists(dir / "sharded" / "report.json")); // a shard leaves the report to --merge
  const CommandResult merge = brushtrace("batch --merge " + q(dir / "sharded"));
  ASSERT_EQ(merge.exitCode, 0) << merge.err;
  EXPECT_EQ(bt::test::withoutTimings(bt::test::readJson(dir / "sharded" / "report.json")),
            bt::test::withoutTimings(bt::test::readJson(dir / "whole" / "report.json")));
  EXPECT_TRUE(fs::is_regular_file(dir / "sharded" / "index.html"));
  fs::remove_all(dir);
}

TEST(BatchCommand, ATimeoutOrACrashIsTheLevelsFailureAndTheBatchGoesOn) {
  const fs::path dir = bt::test::freshTempDir("limits");
  bt::test::writeText(dir / "m.json", smallManifest(dir, R"(, "limits": {"seconds": 0.001})").dump());
  const CommandResult timeout = brushtrace("batch " + q(dir / "m.json") + " -o " + q(dir / "timeout"));
  EXPECT_EQ(timeout.exitCode, 1);
  EXPECT_EQ(statusWords(timeout.out), (std::vector<std::string>{"FAILED", "FAILED"})) << timeout.out;
  const json report = bt::test::readJson(dir / "timeout" / "report.json");
  ASSERT_EQ(report.at("levels").size(), 2u);
  for (const json& level : report["levels"]) {
    ASSERT_EQ(level.at("failures").size(), 1u) << level;
    EXPECT_EQ(level["failures"][0].at("job"), "process");
    EXPECT_EQ(level["failures"][0].at("message").get<std::string>().rfind("timed out after 0.001 s", 0), 0u) << level["failures"][0];
  }
  // 16 MB of address space: the child cannot even load its libraries' data, or dies allocating.
  bt::test::writeText(dir / "m.json", smallManifest(dir, R"(, "limits": {"memory_mb": 16})").dump());
  const CommandResult memory = brushtrace("batch " + q(dir / "m.json") + " -o " + q(dir / "memory"));
  EXPECT_EQ(memory.exitCode, 1);
  EXPECT_EQ(statusWords(memory.out), (std::vector<std::string>{"FAILED", "FAILED"})) << memory.out;
  EXPECT_TRUE(bt::test::partialFiles(dir).empty());
  fs::remove_all(dir);
}

TEST(BatchCommand, BadUsageAndBadManifestsSayWhatIsWrong) {
  const fs::path dir = bt::test::freshTempDir("usage");
  EXPECT_EQ(brushtrace("batch " + q(bt::test::mapsDir() / "start.map")).exitCode, 2); // no -o
  EXPECT_EQ(brushtrace("batch " + q(bt::test::mapsDir() / "start.map") + " -o " + q(dir / "o") + " --shard 3/2").exitCode, 2);
  EXPECT_EQ(brushtrace("batch " + q(bt::test::mapsDir() / "start.map") + " -o /nonexistent/o").exitCode, 2);
  bt::test::writeText(dir / "bad.json",
                      json{{"levels", {(bt::test::mapsDir() / "start.map").string()}}, {"jobs", {{"render", {{"sise", "1x1"}}}}}}.dump());
  CommandResult r = brushtrace("batch " + q(dir / "bad.json") + " -o " + q(dir / "o"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find((dir / "bad.json").string() + ": jobs.render: unknown key 'sise'"), std::string::npos) << r.err;
  bt::test::writeText(dir / "bad.json", "{\"levels\": [\n  \"x.map\",\n}");
  r = brushtrace("batch " + q(dir / "bad.json") + " -o " + q(dir / "o"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("bad.json: [json.exception.parse_error.101] parse error at line 3, column 1"), std::string::npos) << r.err;
  bt::test::writeText(dir / "bad.json", R"({"levels": ["nothing*.map"]})");
  r = brushtrace("batch " + q(dir / "bad.json") + " -o " + q(dir / "o"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("levels[0]: '" + (dir / "nothing*.map").string() + "' matches no level"), std::string::npos) << r.err;
  fs::remove_all(dir);
}

// The value a manifest key takes when absent, for a schema property: its default, else the first
// of its enum.
json schemaDefault(const json& property) {
  if (property.contains("default")) return property.at("default");
  if (property.contains("enum")) return property.at("enum").at(0);
  return nullptr;
}

// Every key of object `schema` (a schema object with properties) at its schema default.
json everyKeyAtItsDefault(const json& schema) {
  json object = json::object();
  for (const auto& [key, property] : schema.at("properties").items()) object[key] = schemaDefault(property);
  return object;
}

// app/batch/manifest.schema.json and the parser (app/batch/batch_manifest.cpp) name the same keys:
// the keys of the parser's requireKnownKeys lists are the schema's properties, a manifest with every
// key the schema lists (each at its default) runs, and a key the schema does not list is an error
// in each of its objects, as additionalProperties false says.
TEST(BatchCommand, TheManifestSchemaNamesTheKeysTheBatchReads) {
  const fs::path source = bt::test::sourceDir();
  std::ifstream schemaFile(source / "app/batch/manifest.schema.json");
  const json schema = json::parse(schemaFile);
  const json &level = schema.at("$defs").at("level"), &render = schema.at("$defs").at("render");
  const json &jobs = schema.at("properties").at("jobs"), &limits = schema.at("properties").at("limits");
  std::set<std::string> schemaKeys;
  for (const json* object : {&schema, &level, &render, &jobs, &limits}) {
    EXPECT_EQ(object->at("additionalProperties"), false);
    for (const auto& [key, property] : object->at("properties").items()) schemaKeys.insert(key);
  }
  std::ifstream parserFile(source / "app/batch/batch_manifest.cpp");
  const std::string parser((std::istreambuf_iterator<char>(parserFile)), std::istreambuf_iterator<char>());
  std::set<std::string> parserKeys;
  const std::regex list(R"(requireKnownKeys\([^{]*\{([^}]*)\})"), key("\"([a-z_]+)\"");
  for (auto m = std::sregex_iterator(parser.begin(), parser.end(), list); m != std::sregex_iterator(); ++m) {
    const std::string keys = (*m)[1];
    for (auto k = std::sregex_iterator(keys.begin(), keys.end(), key); k != std::sregex_iterator(); ++k) parserKeys.insert((*k)[1]);
  }
  EXPECT_EQ(schemaKeys, parserKeys);

  const fs::path dir = bt::test::freshTempDir("schema");
  json levelEntry = everyKeyAtItsDefault(level);
  levelEntry["path"] = (bt::test::mapsDir() / "start.map").string();
  json renderJob = everyKeyAtItsDefault(render);
  renderJob["size"] = "16x9", renderJob["spp"] = 1, renderJob["backend"] = "cpu";
  json manifest = everyKeyAtItsDefault(schema);
  manifest["levels"] = json::array({levelEntry});
  manifest["jobs"] = everyKeyAtItsDefault(jobs);
  manifest["jobs"]["render"] = renderJob;
  manifest["limits"] = everyKeyAtItsDefault(limits);
  bt::test::writeText(dir / "m.json", manifest.dump());
  const CommandResult ok = brushtrace("batch " + q(dir / "m.json") + " -o " + q(dir / "out"));
  EXPECT_EQ(ok.exitCode, 0) << manifest.dump() << "\n" << ok.err;

  for (const json::json_pointer& at : {json::json_pointer(""), json::json_pointer("/levels/0"), json::json_pointer("/jobs"),
                                       json::json_pointer("/jobs/render"), json::json_pointer("/limits")}) {
    json bad = manifest;
    bad[at]["zzz"] = 1;
    bt::test::writeText(dir / "bad.json", bad.dump());
    const CommandResult r = brushtrace("batch " + q(dir / "bad.json") + " -o " + q(dir / "out2"));
    EXPECT_EQ(r.exitCode, 1) << at;
    EXPECT_NE(r.err.find("unknown key 'zzz'"), std::string::npos) << at << ": " << r.err;
  }
  fs::remove_all(dir);
}

// index.html opened from file:// in headless Chromium: check.html, beside it, loads it in a frame
// and writes what the browser made of it (thumbnails decoded, failure rows, the first card)
// into its own DOM, which --dump-dom prints. The screenshot is left in the build folder.
TEST(BatchContactSheet, ChromiumShowsEveryThumbnailAndTheFailuresFirst) {
  const fs::path chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium)) GTEST_SKIP() << "Debian's chromium is not installed: the contact sheet is not checked in a browser";
  const fs::path dir = bt::test::freshTempDir("sheet");
  json manifest = smallManifest(dir);
  bt::test::writeText(dir / "empty.map", "// Format: Standard\n{\n\"classname\" \"worldspawn\"\n}\n");
  bt::test::writeText(dir / "broken.map", "{\n\"classname\" \"worldspawn\"\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a 0 zero 0 1 1\n}\n}\n");
  bt::test::writeText(dir / "m.json", manifest.dump());
  const CommandResult r = brushtrace("batch " + q(dir / "m.json") + " -o " + q(dir / "out"));
  ASSERT_EQ(r.exitCode, 1) << r.err; // two levels failed
  bt::test::writeText(dir / "out" / "check.html", R"(<!DOCTYPE html><html><body><iframe id="f" src="index.html"></iframe><script>
document.getElementById("f").onload = function () {
  const d = this.contentDocument, images = Array.from(d.images);
  const loaded = images.filter(i => i.complete && i.naturalWidth > 0).length;
  const p = document.createElement("pre");
  p.id = "result";
  p.textContent = "images " + images.length + " loaded " + loaded + " failures " + d.querySelectorAll("#failures tr").length +
                  " cards " + Array.from(d.querySelectorAll(".card .name")).map(n => n.textContent).join(",");
  document.body.appendChild(p);
};</script></body></html>)");
  const std::string browser =
      q(chromium) + " --headless --no-sandbox --disable-gpu --allow-file-access-from-files --virtual-time-budget=10000 ";
  const CommandResult dom = bt::test::runShell(browser + "--dump-dom " + q("file://" + (dir / "out" / "check.html").string()));
  // The two levels that rendered have a beauty and an albedo thumbnail each; a row per failure
  // (broken.map: its import and its round trip; empty.map: nothing to draw); the failures come first.
  EXPECT_NE(dom.out.find("<pre id=\"result\">images 4 loaded 4 failures 3 cards broken.map,empty.map,quake2.map,standard.map</pre>"),
            std::string::npos)
      << dom.out << dom.err;
  const fs::path shot = bt::test::binaryDir() / "batch_contact_sheet.png";
  const CommandResult screenshot = bt::test::runShell(browser + "--window-size=1000,700 --screenshot=" + q(shot) + " " +
                                                      q("file://" + (dir / "out" / "index.html").string()));
  EXPECT_TRUE(fs::is_regular_file(shot)) << screenshot.err;
  fs::remove_all(dir);
}

} // namespace
