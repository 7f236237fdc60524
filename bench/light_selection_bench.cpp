// Light selection against the exhaustive light loop (IntegratorSettings::lightSelection), CPU
// tracer, on shared maps with many lights: id's e1m1 (198 light entities), LibreQuake's lq_e4m3
// (1213) and lqdm5 (2,598 with its _surface points, issue 18's many-lights level). One sample
// per pixel of a small frame from the map's default camera, both lighting modes, one thread and
// two. Physical mode's selection is the light grid's near lists (selection 1, what the
// renderer uses) or the light tree (selection 2, lighting/light_tree.h).
//   build/bench/bench_light_selection [--benchmark_filter=...]
// Samples/s is per sample, not per unit of noise: physical selection trades variance per sample
// for far fewer shadow rays (the tests show it converges to the same mean), so the benchmark
// also reports the per-sample variance of pixel luminance relative to the squared image mean;
// time x rel.variance is what it costs to reach a given noise level.
#include "bench/loaded_level.h"
#include "importers/import.h"
#include "renderer/cpu/cpu_renderer.h"

#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <memory>

namespace {

using namespace bt;

// The levels measured: e1m1 (194 lights), lq_e4m3 (the largest shared map, 2590 with its
// _surface points).
const std::map<std::string, std::string> kMaps = {
    {"e1m1", std::string(BRUSHTRACE_SHARED_DIR) + "/maps/quake_map_source/e1m1.map"},
    {"lq_e4m3", std::string(BRUSHTRACE_SHARED_DIR) + "/maps/librequake/lq1/maps/src/e4/lq_e4m3.map"},
    {"lqdm5", std::string(BRUSHTRACE_SHARED_DIR) + "/maps/librequake/lq1/maps/src/dm/lqdm5.map"},
};

constexpr int kWidth = 96, kHeight = 54;

// range(0): threads; range(1): 1 = light selection (physical: the near lists), 2 = physical
// mode's light tree, 0 = every light at every hit.
void BM_LightSelection(benchmark::State& state, const std::string& mapName, LightingMode mode) {
  const bench::LoadedLevel* m = bench::loadLevel(kMaps.at(mapName));
  if (!m) {
    state.SkipWithError("map not found (../shared missing?)");
    return;
  }
  RenderSettings s;
  s.width = kWidth;
  s.height = kHeight;
  s.spp = 1;
  s.threads = int(state.range(0));
  s.integrator.mode = mode;
  s.integrator.lightSelection = state.range(1) != 0;
  if (state.range(1) == 2) s.integrator.physicalPick = IntegratorSettings::PhysicalPick::Tree;
  const Camera camera(m->pose, kWidth, kHeight);
  RenderImage image;
  for (auto _ : state) {
    image = renderCpu(m->rs, camera, s);
    benchmark::DoNotOptimize(image.beauty.data());
  }
  // Noise per sample: two 1-spp images of other seeds differ by 2x the per-sample variance.
  // Selection is worth it when variance x time drops, not just time.
  s.seed = 1;
  const RenderImage other = renderCpu(m->rs, camera, s);
  double variance = 0.0, mean = 0.0;
  for (size_t i = 0; i < image.beauty.size(); ++i) {
    const float a = (image.beauty[i].x + image.beauty[i].y + image.beauty[i].z) / 3.0f;
    const float b = (other.beauty[i].x + other.beauty[i].y + other.beauty[i].z) / 3.0f;
    variance += 0.5 * double(a - b) * double(a - b);
    mean += 0.5 * double(a + b);
  }
  state.counters["rel.variance"] = mean > 0.0 ? variance * double(image.beauty.size()) / (mean * mean) : 0.0;
  const double samples = double(kWidth) * kHeight * double(state.iterations());
  state.counters["samples/s"] = benchmark::Counter(samples, benchmark::Counter::kIsRate);
  // Seconds per sample per pixel of a 320x180 frame, the size the numbers are quoted at.
  state.counters["s/spp@320x180"] =
      benchmark::Counter(samples / (320.0 * 180.0), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["lights"] = double(m->rs.lights.size());
  const LightGrid& grid = m->rs.lightGrid;
  const size_t cellCount = grid.cells.size() / 2;
  double listed = 0.0;
  for (size_t c = 0; c < cellCount; ++c) listed += grid.cells[c].count;
  state.counters["cells"] = double(cellCount);
  // Lights a faithful hit looks at, on average over cells (every light without the grid).
  state.counters["faithful/cell"] = double(grid.header.fixedCount + grid.header.globalCount) + listed / double(cellCount);
}

void threadsAndSelection(benchmark::internal::Benchmark* b) {
  b->ArgNames({"threads", "selection"});
  for (int threads : {1, 2})
    for (int selection : {0, 1}) b->Args({threads, selection});
  b->UseRealTime()->Unit(benchmark::kMillisecond)->MinTime(0.5);
}

// Physical mode's near lists against the tree, and the exhaustive loop once (lqdm5's takes
// seconds a frame).
void physicalPicks(benchmark::internal::Benchmark* b) {
  b->ArgNames({"threads", "selection"});
  for (int selection : {1, 2}) b->Args({2, selection});
  b->Args({2, 0});
  b->UseRealTime()->Unit(benchmark::kMillisecond)->MinTime(0.5);
}

} // namespace

BENCHMARK_CAPTURE(BM_LightSelection, e1m1_faithful, std::string("e1m1"), LightingMode::Faithful)->Apply(threadsAndSelection);
BENCHMARK_CAPTURE(BM_LightSelection, e1m1_physical, std::string("e1m1"), LightingMode::Physical)->Apply(threadsAndSelection);
BENCHMARK_CAPTURE(BM_LightSelection, lq_e4m3_faithful, std::string("lq_e4m3"), LightingMode::Faithful)->Apply(threadsAndSelection);
BENCHMARK_CAPTURE(BM_LightSelection, lq_e4m3_physical, std::string("lq_e4m3"), LightingMode::Physical)->Apply(threadsAndSelection);
BENCHMARK_CAPTURE(BM_LightSelection, lq_e4m3_physical_picks, std::string("lq_e4m3"), LightingMode::Physical)->Apply(physicalPicks);
BENCHMARK_CAPTURE(BM_LightSelection, lqdm5_physical_picks, std::string("lqdm5"), LightingMode::Physical)->Apply(physicalPicks);

BENCHMARK_MAIN();
