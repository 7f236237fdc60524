// What `brushtrace render` and `bench` do between reading a level and uploading it: the import
// and buildRenderScene (lights, surface light points, emitters, BVH, light grid), on the largest
// shared map (LibreQuake lq_e4m3: 3399 brushes, 2685 lights), a mid-sized one (lqdm5) and the
// largest oracle .bsp; a level with `_bounce` (lq_e3m1), whose bounce lights are made here too;
// plus the light grid alone, the largest single step, and on lq_e3m1 its bounce lights added to
// the direct lights' grid (what buildRenderScene does) against the grid made at once.
//   build/bench/bench_prepare_level [--benchmark_filter=...]
#include "importers/import.h"
#include "lighting/lights.h"
#include "lighting/render_scene.h"

#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <string>

namespace {

using namespace bt;

const std::string kShared = BRUSHTRACE_SHARED_DIR;
const std::map<std::string, std::string> kLevels = {
    {"lq_e4m3", kShared + "/maps/librequake/lq1/maps/src/e4/lq_e4m3.map"},
    {"lqdm5", kShared + "/maps/librequake/lq1/maps/src/dm/lqdm5.map"},
    {"lq_e4m3_bsp", kShared + "/oracle/maps_librequake_lq1_maps_src_e4_lq_e4m3.bsp"},
    {"lq_e3m1", kShared + "/maps/librequake/lq1/maps/src/e3/lq_e3m1.map"}, // _bounce 3
};

bool present(benchmark::State& state, const std::string& path) {
  if (std::filesystem::exists(path)) return true;
  state.SkipWithError(("not found (../shared missing?): " + path).c_str());
  return false;
}

void BM_Import(benchmark::State& state, const std::string& level) {
  const std::string& path = kLevels.at(level);
  if (!present(state, path)) return;
  for (auto _ : state) benchmark::DoNotOptimize(importScene(path, ImportOptions{}).faces.data());
}

void BM_BuildRenderScene(benchmark::State& state, const std::string& level) {
  const std::string& path = kLevels.at(level);
  if (!present(state, path)) return;
  const Scene scene = importScene(path, ImportOptions{});
  size_t lights = 0;
  for (auto _ : state) {
    Diagnostics diagnostics;
    const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
    lights = rs.lights.size();
    benchmark::DoNotOptimize(rs.lightGrid.indices.data());
  }
  state.counters["lights"] = double(lights);
}

// What the GL renderer's level preparation does (renderer/gl/gl_level.cpp LevelPreparation): the
// import, the light kinds and level parts told as soon as the entities are read, then
// buildRenderScene with the vis boxes left to the GPU. Its wall time is how long the first image
// can wait for the level.
void BM_PrepareGlLevel(benchmark::State& state, const std::string& level) {
  const std::string& path = kLevels.at(level);
  if (!present(state, path)) return;
  RenderSceneOptions options;
  options.visApproxBoxes = RenderSceneOptions::VisBoxes::Gpu;
  for (auto _ : state) {
    Diagnostics diagnostics;
    bool told = false;
    auto tell = [&](const Scene& read) {
      if (told) return;
      benchmark::DoNotOptimize(lightKinds(read, collectLights(read, options.lights, diagnostics), options.bounceLights));
      benchmark::DoNotOptimize(levelParts(read, options));
      told = true;
    };
    const Scene scene = importScene(path, ImportOptions{}, tell);
    tell(scene); // an importer that did not say when it had the entities
    const RenderScene rs = buildRenderScene(scene, options, diagnostics);
    benchmark::DoNotOptimize(rs.lightGrid.indices.data());
  }
}

void BM_BuildLightGrid(benchmark::State& state, const std::string& level) {
  const std::string& path = kLevels.at(level);
  if (!present(state, path)) return;
  const Scene scene = importScene(path, ImportOptions{});
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  for (auto _ : state) benchmark::DoNotOptimize(buildLightGrid(rs.lights, rs.tracer.bounds(), rs.world.scaledist).indices.data());
  state.counters["cells"] = double(rs.lightGrid.cells.size() / 2);
}

// A `_bounce` level's grid as buildRenderScene makes it: the direct lights' grid, then the bounce
// lights added to it (extendLightGrid), against BM_BuildLightGrid's grid of every light at once.
void BM_ExtendLightGrid(benchmark::State& state, const std::string& level) {
  const std::string& path = kLevels.at(level);
  if (!present(state, path)) return;
  const Scene scene = importScene(path, ImportOptions{});
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  RenderSceneOptions directOnly;
  directOnly.bounceLights = false;
  const RenderScene direct = buildRenderScene(scene, directOnly, diagnostics);
  for (auto _ : state)
    benchmark::DoNotOptimize(
        extendLightGrid(direct.lightGrid, rs.lights, uint32_t(direct.lights.size()), rs.tracer.bounds(), rs.world.scaledist)
            .indices.data());
  state.counters["added"] = double(rs.lights.size() - direct.lights.size());
}

} // namespace

BENCHMARK_CAPTURE(BM_Import, lq_e4m3, std::string("lq_e4m3"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_BuildRenderScene, lq_e4m3, std::string("lq_e4m3"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_PrepareGlLevel, lq_e4m3, std::string("lq_e4m3"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_BuildLightGrid, lq_e4m3, std::string("lq_e4m3"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Import, lqdm5, std::string("lqdm5"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_BuildRenderScene, lqdm5, std::string("lqdm5"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_PrepareGlLevel, lqdm5, std::string("lqdm5"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_BuildRenderScene, lq_e3m1, std::string("lq_e3m1"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_BuildLightGrid, lq_e3m1, std::string("lq_e3m1"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ExtendLightGrid, lq_e3m1, std::string("lq_e3m1"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Import, lq_e4m3_bsp, std::string("lq_e4m3_bsp"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_BuildRenderScene, lq_e4m3_bsp, std::string("lq_e4m3_bsp"))->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
