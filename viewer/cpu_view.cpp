#include "viewer/cpu_view.h"

#include "lighting/sampling.h"
#include "renderer/cpu/integrator.h"
#include "renderer/exposure.h" // luminance
#include "renderer/view_lightmaps.h"
#include "scene/parallel_for.h"

#include <algorithm>
#include <cmath>

namespace bt {

namespace {
using Clock = std::chrono::steady_clock;
// The most rows a band takes (a view of sky, which costs nothing, would otherwise be one band).
constexpr int kMaxBandRows = 64;
} // namespace

CpuProgressive::CpuProgressive(int width, int height)
    : width_(width), height_(height), sum_(size_t(width) * size_t(height)), moment2_(sum_.size(), 0.0), rowSamples_(size_t(height), 0) {}

void CpuProgressive::restart() {
  std::fill(sum_.begin(), sum_.end(), glm::dvec3(0.0));
  std::fill(moment2_.begin(), moment2_.end(), 0.0);
  std::fill(rowSamples_.begin(), rowSamples_.end(), 0);
  passes_ = 0;
  nextRow_ = 0;
}

size_t CpuProgressive::refine(const RenderScene& scene, const Camera& camera, const IntegratorSettings& integrator,
                              std::chrono::duration<double> budget, int maxSamples) {
  const auto start = Clock::now();
  size_t traced = 0;
  while (passes_ < maxSamples) {
    // Bands of about a quarter of the budget, by the last band's time per row, and none that
    // would end past the budget (but one at least): a frame ends near its budget, not a band late.
    const int wanted = secondsPerRow_ > 0.0 ? int(0.25 * budget.count() / secondsPerRow_) : 1; // one row to time first
    const int rows = std::min(std::clamp(wanted, 1, kMaxBandRows), height_ - nextRow_);
    const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    if (traced > 0 && elapsed + rows * secondsPerRow_ > budget.count()) break;
    const int first = nextRow_;
    const auto bandStart = Clock::now();
    parallelFor(size_t(rows) * size_t(width_), 0, [&](size_t i) {
      const int x = int(i % size_t(width_)), y = first + int(i / size_t(width_));
      Rng rng = pathRng(integrator, uint32_t(x), uint32_t(y), uint32_t(passes_), 0);
      const glm::vec2 jitter = rng.next2();
      rng.atPcg();
      const glm::vec3 l = radiance(scene, integrator, camera.ray(float(x) + jitter.x, float(y) + jitter.y), rng);
      // A NaN or infinite sample would poison the pixel for good; drop it (as renderCpu does).
      if (!(std::isfinite(l.x) && std::isfinite(l.y) && std::isfinite(l.z))) return;
      sum_[size_t(y) * width_ + x] += glm::dvec3(l);
      moment2_[size_t(y) * width_ + x] += double(luminance(l)) * double(luminance(l));
    });
    secondsPerRow_ = std::chrono::duration<double>(Clock::now() - bandStart).count() / rows;
    for (int y = first; y < first + rows; ++y) ++rowSamples_[size_t(y)];
    traced += size_t(rows) * size_t(width_);
    nextRow_ += rows;
    if (nextRow_ == height_) {
      nextRow_ = 0;
      ++passes_;
    }
  }
  return traced;
}

RenderImage CpuProgressive::mean() const {
  RenderImage image;
  image.width = width_;
  image.height = height_;
  image.samples = passes_;
  image.beauty.assign(sum_.size(), glm::vec3(0.0f));
  image.luminanceMoment2.assign(sum_.size(), 0.0f);
  for (int y = 0; y < height_; ++y) {
    const int n = rowSamples_[size_t(y)];
    if (n == 0) continue;
    for (int x = 0; x < width_; ++x) {
      const size_t i = size_t(y) * width_ + x;
      image.beauty[i] = glm::vec3(sum_[i] / double(n));
      image.luminanceMoment2[i] = float(moment2_[i] / double(n));
    }
  }
  return image;
}

CpuLuxelBake::CpuLuxelBake(const RenderScene& scene, LightmapBakeOptions options, bool styled)
    : baking_(std::async(std::launch::async, [&scene, options, styled] {
        Baked baked{layoutFaithfulLightmaps(scene, nullptr, 0, 0, options.threads), {}};
        if (styled)
          baked.styled = bakeStyledLuxels(scene, baked.lightmaps, options);
        else
          bakeLightmaps(scene, baked.lightmaps, options);
        return baked;
      })) {}

CpuLuxelBake::~CpuLuxelBake() {
  if (baking_.valid()) baking_.wait();
}

bool CpuLuxelBake::ready() const {
  return taken_ || baking_.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

bool CpuLuxelBake::takeInto(RenderScene& scene, std::span<const float, 256> styleWeights, StyledLuxels* styled) {
  if (taken_ || !ready()) return false;
  Baked baked = baking_.get();
  scene.lightmaps = std::move(baked.lightmaps);
  if (!baked.styled.styles.empty()) scene.lightmaps.luxels = sumStyles(baked.styled, styleWeights);
  if (styled) *styled = std::move(baked.styled);
  taken_ = true;
  return true;
}

} // namespace bt
