#include "app/batch/batch_level.h"

#include "app/batch/batch_files.h"
#include "app/render_options.h"
#include "importers/map/map_parser.h"
#include "importers/map/map_writer.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <new>
#include <filesystem>

namespace bt::app::batch {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

class Stopwatch {
public:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// Timings are kept to the millisecond: they are figures for people, and the report stays readable.
double rounded(double seconds) {
  return std::round(seconds * 1000.0) / 1000.0;
}

json diagnosticJson(const Diagnostic& d) {
  const char* severity = d.severity == Severity::Error ? "error" : d.severity == Severity::Warning ? "warning" : "note";
  return {{"severity", severity}, {"file", d.file}, {"line", d.line}, {"column", d.column}, {"message", d.message}};
}

// The file a level path names: the archive of ARCHIVE:maps/x.bsp; none for a bare level name.
std::vector<std::string> levelFiles(const std::string& path) {
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) return {path};
  const size_t colon = path.find(':');
  if (colon != std::string::npos && fs::is_regular_file(path.substr(0, colon), ec)) return {path.substr(0, colon)};
  return {};
}

bool isMapSource(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".map" && fs::is_regular_file(path);
}

// convert's same-dialect rewrite, read back: lossless means the same document (the check
// tests/map/map_shared_test.cpp makes of every shared map).
json roundTrip(const Level& level, json& failures) {
  const Stopwatch clock;
  const map::MapDocument doc = map::readMapFile(level.path, level.import.dialect);
  Diagnostics report;
  const std::string text = map::writeMap(map::convertDocument(doc, doc.dialect, report));
  const bool same = map::parseMap(text, level.path + " (rewritten)") == doc;
  if (!same) failures.push_back({{"job", "roundtrip"}, {"message", "the same-dialect rewrite reads back as a different document"}});
  return {{"dialect", toString(doc.dialect)},
          {"lossless", same},
          {"bytes", text.size()},
          {"sha256", sha256Hex(text)},
          {"seconds", rounded(clock.seconds())}};
}

std::vector<std::optional<CameraPose>> camerasOf(const Scene& scene, int spawnCameras) {
  std::vector<std::optional<CameraPose>> cameras{std::nullopt}; // the default camera, as `render` picks it
  const CameraPose first = defaultCameraPose(scene);
  for (const CameraPose& pose : spawnCameraPoses(scene)) {
    if (int(cameras.size()) > spawnCameras) break;
    if (pose.origin != first.origin) cameras.push_back(pose);
  }
  return cameras;
}

RenderOptions renderOptions(const Level& level, const RenderJob& job) {
  RenderOptions o;
  o.map = level.path;
  o.import = level.import;
  o.size = job.size;
  o.spp = job.spp;
  o.timeLimit = job.seconds;
  o.backend = job.backend;
  o.seed = job.seed;
  o.quiet = true;
  return o;
}

json renders(const Level& level, const Scene& scene, const RenderJob& job, const std::string& workDir, const std::string& imagePrefix,
             json& failures) {
  json images = json::array();
  const auto cameras = camerasOf(scene, job.spawnCameras);
  for (size_t c = 0; c < cameras.size(); ++c)
    for (const std::string& lighting : job.lighting)
      for (const std::string& aov : job.aovs) {
        RenderOptions o = renderOptions(level, job);
        o.camera = cameras[c];
        o.lighting = lighting;
        o.aov = aov;
        const std::string name = fmt::format("camera{}-{}-{}.png", c, lighting, aov);
        o.output = (fs::path(workDir) / "images" / name).string();
        const Stopwatch clock;
        RenderOutcome outcome;
        if (runRender(o, &outcome) != 0) {
          failures.push_back({{"job", "render"}, {"message", "the level has no face to draw; no image written"}});
          return images;
        }
        images.push_back({{"image", imagePrefix + name},
                          {"camera", formatCameraPose(outcome.pose)},
                          {"source", outcome.pose.source},
                          {"lighting", lighting},
                          {"aov", aov},
                          {"samples", outcome.samples},
                          {"device", outcome.device},
                          {"sha256", sha256File(o.output)},
                          {"seconds", rounded(clock.seconds())}});
      }
  return images;
}

// Runs one job, recording an exception as the job's failure: the level's other jobs still run.
template <class Job> void guarded(const char* name, json& failures, Job&& job) {
  try {
    job();
  } catch (const std::bad_alloc&) {
    failures.push_back({{"job", name}, {"message", "out of memory (the batch's memory limit, limits.memory_mb)"}});
  } catch (const std::exception& e) {
    failures.push_back({{"job", name}, {"message", e.what()}});
  }
}

} // namespace

json runLevelJobs(const Level& level, const Jobs& jobs, const std::string& workDir, const std::string& imagePrefix) {
  const Stopwatch clock;
  json result{{"id", level.id}, {"level", level.path}};
  json failures = json::array();
  std::vector<std::string> inputs = levelFiles(level.path);
  std::optional<Scene> scene;
  const Stopwatch importClock;
  guarded("import", failures, [&] { scene = importScene(level.path, level.import); });
  if (scene) {
    for (const std::string& file : scene->inputFiles)
      if (std::find(inputs.begin(), inputs.end(), file) == inputs.end()) inputs.push_back(file);
    if (jobs.import) {
      json diagnostics = json::array();
      for (const Diagnostic& d : scene->diagnostics) diagnostics.push_back(diagnosticJson(d));
      result["import"] = {{"info", infoJson(*scene)}, {"diagnostics", diagnostics}, {"seconds", rounded(importClock.seconds())}};
    }
  }
  if (jobs.roundTrip && isMapSource(level.path)) guarded("roundtrip", failures, [&] { result["roundtrip"] = roundTrip(level, failures); });
  if (jobs.render && scene)
    guarded("render", failures, [&] { result["renders"] = renders(level, *scene, *jobs.render, workDir, imagePrefix, failures); });
  result["inputs"] = hashInputs(inputs);
  result["failures"] = failures;
  result["status"] = failures.empty() ? "ok" : "failed";
  result["seconds"] = rounded(clock.seconds());
  return result;
}

json failedLevel(const Level& level, const std::string& job, const std::string& message) {
  return {{"id", level.id},
          {"level", level.path},
          {"inputs", hashInputs(levelFiles(level.path))},
          {"failures", json::array({{{"job", job}, {"message", message}}})},
          {"status", "failed"}};
}

json hashInputs(const std::vector<std::string>& files) {
  json inputs = json::array();
  for (const std::string& file : files) {
    std::error_code ec;
    // A folder of loose images counts by its listing; its images are inputs of their own.
    inputs.push_back({{"path", file}, {"sha256", fs::is_regular_file(file, ec) ? sha256File(file) : std::string("missing")}});
  }
  return inputs;
}

std::string inputHash(const json& inputs, const std::string& jobHash) {
  return sha256Hex(jobHash + inputs.dump());
}

} // namespace bt::app::batch
