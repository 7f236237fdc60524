// Faithful `_bounce` preparation (renderer/cpu/bounce.h): buildRenderScene on LibreQuake's
// lq_e4m3, the largest shared map, as it is (no bounce) and with worldspawn `_bounce 1` forced.
// The difference is the bounce lights' cost: the mean direct light over every luxel of every
// compiled face, on all cores, once per scene.
//   build/bench/bench_bounce
#include "importers/import.h"
#include "renderer/cpu/render_scene.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <string>

namespace {

using namespace bt;

const std::string kMap = std::string(BRUSHTRACE_SHARED_DIR) + "/maps/librequake/lq1/maps/src/e4/lq_e4m3.map";

// range(0): the forced `_bounce` (0 = the level's own keys, which bounce nothing).
void BM_BuildRenderScene(benchmark::State& state) {
  if (!std::filesystem::exists(kMap)) {
    state.SkipWithError("map not found (../shared missing?)");
    return;
  }
  Scene scene = importScene(kMap, ImportOptions{});
  if (state.range(0) > 0 && !scene.entities.empty())
    scene.entities[0].keys.emplace_back("_bounce", std::to_string(state.range(0)));
  size_t bounceLights = 0;
  for (auto _ : state) {
    Diagnostics diagnostics;
    const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
    bounceLights = size_t(std::count_if(rs.lights.begin(), rs.lights.end(),
                                        [](const GpuLight& l) { return l.formula == uint32_t(LightFormula::Bounce); }));
    benchmark::DoNotOptimize(rs.lights.data());
  }
  state.counters["bounce_lights"] = double(bounceLights);
}
BENCHMARK(BM_BuildRenderScene)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

} // namespace

BENCHMARK_MAIN();
