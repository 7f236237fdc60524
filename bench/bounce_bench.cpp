// Faithful `_bounce` preparation (lighting/bounce.h): buildRenderScene on LibreQuake's
// lq_e4m3, the largest shared map, as it is (no bounce) and with worldspawn `_bounce 1` forced,
// and on lq_e3m1, whose worldspawn sets `_bounce 3`, without and with its bounce lights.
// The difference is the bounce lights' cost: the mean direct light over each compiled face's
// luxels (all of them, or BounceBudget's subset on these large levels), on all cores, once per
// scene.
//   build/bench/bench_bounce
#include "importers/import.h"
#include "lighting/render_scene.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <string>

namespace {

using namespace bt;

const std::string kMaps = std::string(BRUSHTRACE_SHARED_DIR) + "/maps/librequake/lq1/maps/src/";
const std::string kE4m3 = kMaps + "e4/lq_e4m3.map";
const std::string kE3m1 = kMaps + "e3/lq_e3m1.map";

// Builds the render scene of `scene` once per iteration; counts its bounce lights.
void buildOnce(benchmark::State& state, const Scene& scene, const RenderSceneOptions& options) {
  size_t bounceLights = 0;
  std::string note;
  for (auto _ : state) {
    Diagnostics diagnostics;
    const RenderScene rs = buildRenderScene(scene, options, diagnostics);
    bounceLights = size_t(
        std::count_if(rs.lights.begin(), rs.lights.end(), [](const GpuLight& l) { return l.formula == uint32_t(LightFormula::Bounce); }));
    for (const Diagnostic& d : diagnostics)
      if (d.message.starts_with("_bounce")) note = d.message;
    benchmark::DoNotOptimize(rs.lights.data());
  }
  state.counters["bounce_lights"] = double(bounceLights);
  state.SetLabel(note);
}

// range(0): the forced `_bounce` (0 = the level's own keys, which bounce nothing).
void BM_BuildRenderScene(benchmark::State& state) {
  if (!std::filesystem::exists(kE4m3)) {
    state.SkipWithError("map not found (../shared missing?)");
    return;
  }
  Scene scene = importScene(kE4m3, ImportOptions{});
  if (state.range(0) > 0 && !scene.entities.empty()) scene.entities[0].keys.emplace_back("_bounce", std::to_string(state.range(0)));
  buildOnce(state, scene, {});
}
BENCHMARK(BM_BuildRenderScene)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

// lq_e3m1 as it is (`_bounce 3`); range(0): 1 = with its bounce lights, 0 = without.
void BM_BuildRenderSceneE3m1(benchmark::State& state) {
  if (!std::filesystem::exists(kE3m1)) {
    state.SkipWithError("map not found (../shared missing?)");
    return;
  }
  const Scene scene = importScene(kE3m1, ImportOptions{});
  RenderSceneOptions options;
  options.bounceLights = state.range(0) != 0;
  buildOnce(state, scene, options);
}
BENCHMARK(BM_BuildRenderSceneE3m1)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

} // namespace

BENCHMARK_MAIN();
