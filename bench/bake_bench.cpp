// Faithful mode's light compiler (lighting/lightmap_bake.h) on whole levels: the layout of
// qbsp's faces and their luxel grids, then the bake of every luxel on all cores, against
// ericw-tools `light` on the same level (its own log in ../shared/oracle/lit/ gives its time).
//   build/bench/bench_bake [--benchmark_filter=...]
#include "importers/import.h"
#include "lighting/lightmap_bake.h"

#include <benchmark/benchmark.h>

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>

#include <fmt/format.h>

namespace {

using namespace bt;

const std::string kShared = BRUSHTRACE_SHARED_DIR;
const std::map<std::string, std::string> kLevels = {
    {"lqdm5", kShared + "/maps/librequake/lq1/maps/src/dm/lqdm5.map"}, // 2 598 lights, 939 584 luxels compiled
    {"e1m1", kShared + "/maps/quake_map_source/e1m1.map"},
    {"lq_e4m3", kShared + "/maps/librequake/lq1/maps/src/e4/lq_e4m3.map"},
};

struct Level {
  Scene scene;
  RenderScene rs;
};

Level* prepare(benchmark::State& state, const std::string& name) {
  const std::string& path = kLevels.at(name);
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("not found (../shared missing?): " + path).c_str());
    return nullptr;
  }
  static std::map<std::string, std::unique_ptr<Level>> cache;
  auto& level = cache[name];
  if (!level) {
    level = std::make_unique<Level>();
    ImportOptions options;
    options.textures.load = false;
    level->scene = importScene(path, options);
    Diagnostics diagnostics;
    level->rs = buildRenderScene(level->scene, {}, diagnostics);
  }
  return level.get();
}

// FNV-1a over the luxels: a speed-up of the bake must leave this label unchanged.
std::string luxelHash(const Lightmaps& lm) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (uint32_t v : lm.luxels) h = (h ^ v) * 0x100000001b3ull;
  return fmt::format("luxels {:016x}", h);
}

void BM_Layout(benchmark::State& state, const std::string& name) {
  Level* level = prepare(state, name);
  if (!level) return;
  size_t luxels = 0;
  for (auto _ : state) luxels = layoutLightmaps(level->rs).luxels.size();
  state.counters["luxels"] = double(luxels);
}

void BM_Bake(benchmark::State& state, const std::string& name) {
  Level* level = prepare(state, name);
  if (!level) return;
  const Lightmaps layout = layoutLightmaps(level->rs);
  for (auto _ : state) {
    Lightmaps lm = layout;
    bakeLightmaps(level->rs, lm);
    benchmark::DoNotOptimize(lm.luxels.data());
    state.SetLabel(luxelHash(lm));
  }
  state.counters["luxels"] = double(layout.luxels.size());
  state.counters["luxels/s"] = benchmark::Counter(double(layout.luxels.size()), benchmark::Counter::kIsIterationInvariantRate);
}

// A slice of a level, every 12th face that has a lightmap, with the shadow cache on (1) or off
// (0): a figure in seconds that scales to the whole level by luxels/s.
void BM_BakeSlice(benchmark::State& state, const std::string& name) {
  Level* level = prepare(state, name);
  if (!level) return;
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < level->rs.scene->faces.size(); ++f)
    if (faceHasLightmap(level->rs, f) && f % 12 == 0) faces.push_back(f);
  const Lightmaps layout = layoutLightmaps(level->rs, faces);
  LightmapBakeOptions options;
  options.shadowCache = state.range(0) != 0;
  for (auto _ : state) {
    Lightmaps lm = layout;
    bakeLightmaps(level->rs, lm, options);
    benchmark::DoNotOptimize(lm.luxels.data());
    state.SetLabel(luxelHash(lm));
  }
  state.counters["luxels"] = double(layout.luxels.size());
  state.counters["luxels/s"] = benchmark::Counter(double(layout.luxels.size()), benchmark::Counter::kIsIterationInvariantRate);
}

} // namespace

BENCHMARK_CAPTURE(BM_BakeSlice, lqdm5, std::string("lqdm5"))
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_Layout, e1m1, std::string("e1m1"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Bake, e1m1, std::string("e1m1"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Layout, lqdm5, std::string("lqdm5"))
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_Bake, lqdm5, std::string("lqdm5"))
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_Bake, lq_e4m3, std::string("lq_e4m3"))
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK_MAIN();
