#include "renderer/cpu/cpu_renderer.h"

#include "lighting/liquids.h"
#include "renderer/exposure.h" // luminance
#include "lighting/sky.h"

#include "scene/color.h"
#include "scene/parallel_for.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <thread>
#include <unistd.h>

namespace bt {

namespace {

int threadCount(int requested) {
  if (requested > 0) return requested;
  return std::max(1, int(std::thread::hardware_concurrency()));
}

// Runs rowFn(y) for every row on `threads` workers; rows are handed out one at a time.
template <class RowFn> void forEachRow(int height, int threads, const RowFn& rowFn) {
  parallelFor(size_t(std::max(height, 0)), unsigned(std::max(threads, 1)), [&](size_t y) { rowFn(int(y)); });
}

glm::vec3 surfaceAlbedo(const RenderScene& scene, const Ray& ray, const SurfaceHit& hit) {
  if (!hit.found) return glm::vec3(0.0f);
  const bool sky = (scene.faceFlags[hit.face] & kFaceSky) && scene.sky.size > 0; // its images along the ray
  return sky ? skyRadiance(scene.sky, ray.direction) : srgbToLinear(glm::vec3(baseColorAt(scene, hit.face, hit.position)));
}

// The albedo at the camera ray's surface `hit`; a translucent liquid's blended over what lies
// behind it as the engine blends colours (lighting/liquids.h, in their gamma space), going on
// along the camera's line as aov.comp does.
glm::vec3 albedoAlong(const RenderScene& scene, const Ray& ray, SurfaceHit hit) {
  glm::vec3 veil(0.0f), keep(1.0f);
  for (bool veiled = false;; veiled = true) {
    const glm::vec3 albedo = surfaceAlbedo(scene, ray, hit);
    const LiquidBlend blend = hit.found && (scene.faceFlags[hit.face] & kFaceLiquid)
        ? liquidBlend(scene.materials[gpuFace(scene, hit.face).material])
        : LiquidBlend{};
    if (!(blend.behind > 0.0f)) return veiled ? srgbToLinear(veil + keep * linearToSrgb(albedo)) : albedo;
    veil += keep * blend.self * linearToSrgb(albedo);
    keep *= behindWeight(blend, linearToSrgb(albedo));
    const glm::vec3 toSurface = hit.position - ray.origin;
    const float t = glm::length(toSurface);
    hit = traceVisible(scene, Ray{ray.origin, continueRayAfter(t), toSurface / t, std::numeric_limits<float>::infinity()});
  }
}

void renderAovs(const RenderScene& scene, const Camera& camera, RenderImage& image, int threads) {
  forEachRow(image.height, threads, [&](int y) {
    for (int x = 0; x < image.width; ++x) {
      const size_t i = size_t(y) * image.width + x;
      const Ray ray = camera.ray(float(x) + 0.5f, float(y) + 0.5f);
      const SurfaceHit hit = traceVisible(scene, ray);
      if (!hit.found) continue;
      image.albedo[i] = albedoAlong(scene, ray, hit);
      image.normal[i] = hit.normal;
      image.depth[i] = hit.t;
      image.face[i] = hit.face + 1;
    }
  });
}

} // namespace

RenderImage renderCpu(const RenderScene& scene, const Camera& camera, const RenderSettings& settings,
                      const std::function<void(const RenderProgress&)>& progress) {
  RenderImage image;
  image.width = settings.width;
  image.height = settings.height;
  const size_t n = size_t(image.width) * size_t(image.height);
  image.beauty.assign(n, glm::vec3(0.0f));
  image.albedo.assign(n, glm::vec3(0.0f));
  image.normal.assign(n, glm::vec3(0.0f));
  image.depth.assign(n, std::numeric_limits<float>::infinity());
  image.face.assign(n, 0u);
  const int threads = threadCount(settings.threads);
  renderAovs(scene, camera, image, threads);

  // Sums in double: many samples of bright lights would lose the dim ones in float.
  std::vector<glm::dvec3> sum(n, glm::dvec3(0.0));
  std::vector<double> moment2(n, 0.0); // each sample's luminance squared: the denoiser's variance

  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const int maxSamples = settings.spp > 0 ? settings.spp : std::numeric_limits<int>::max();
  int pass = 0;
  // Each pass adds one sample to every pixel, so a pixel's samples are summed in index order
  // whatever the thread count: the image depends only on seed and sample count.
  while (pass < maxSamples) {
    forEachRow(image.height, threads, [&](int y) {
      for (int x = 0; x < image.width; ++x) {
        Rng rng = pathRng(settings.integrator, uint32_t(x), uint32_t(y), uint32_t(pass), settings.seed);
        const glm::vec2 jitter = rng.next2();
        rng.atPcg();
        const Ray ray = camera.ray(float(x) + jitter.x, float(y) + jitter.y);
        const glm::vec3 l = radiance(scene, settings.integrator, ray, rng);
        // A NaN or infinite sample would poison the pixel for good; drop it.
        if (!(std::isfinite(l.x) && std::isfinite(l.y) && std::isfinite(l.z))) continue;
        const size_t i = size_t(y) * image.width + x;
        sum[i] += glm::dvec3(l);
        moment2[i] += double(luminance(l)) * double(luminance(l));
      }
    });
    ++pass;
    const double t = elapsed();
    if (progress) {
      RenderProgress p;
      p.samplesDone = pass;
      p.samplesTotal = settings.spp;
      p.elapsed = t;
      const double perPass = t / pass;
      p.estimatedRemaining =
          settings.timeLimit > 0.0 && settings.spp <= 0 ? std::max(0.0, settings.timeLimit - t) : perPass * (maxSamples - pass);
      if (settings.timeLimit > 0.0) p.estimatedRemaining = std::min(p.estimatedRemaining, std::max(0.0, settings.timeLimit - t));
      progress(p);
    }
    if (settings.timeLimit > 0.0 && t >= settings.timeLimit) break;
  }
  image.samples = pass;
  image.luminanceMoment2.resize(n);
  for (size_t i = 0; i < n; ++i) {
    image.beauty[i] = glm::vec3(sum[i] / double(std::max(pass, 1)));
    image.luminanceMoment2[i] = float(moment2[i] / double(std::max(pass, 1)));
  }
  return image;
}

RenderImage renderAovsCpu(const RenderScene& scene, const Camera& camera, int width, int height, int threads) {
  RenderImage image;
  image.width = width;
  image.height = height;
  const size_t n = size_t(width) * size_t(height);
  image.beauty.assign(n, glm::vec3(0.0f));
  image.albedo.assign(n, glm::vec3(0.0f));
  image.normal.assign(n, glm::vec3(0.0f));
  image.depth.assign(n, std::numeric_limits<float>::infinity());
  image.face.assign(n, 0u);
  renderAovs(scene, camera, image, threadCount(threads));
  return image;
}

} // namespace bt
