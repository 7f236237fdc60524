#include "renderer/denoise.h"

#include "renderer/exposure.h" // luminance
#include "shaders/denoise_constants.glsl"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <thread>

namespace bt {

namespace {

constexpr float kKernel[3] = {BT_DENOISE_KERNEL0, BT_DENOISE_KERNEL1, BT_DENOISE_KERNEL2};
constexpr float kVarianceKernel[3] = {BT_DENOISE_VARIANCE_KERNEL0, BT_DENOISE_VARIANCE_KERNEL1, BT_DENOISE_VARIANCE_KERNEL2};

// What each pass filters: rgb the irradiance (the beauty divided by the albedo), a the variance
// of its luminance (shaders/denoise.comp's images hold the same).
using Pixels = std::vector<glm::vec4>;

struct Guide {
  int width, height;
  const std::vector<glm::vec3>& albedo;
  const std::vector<glm::vec3>& normal;
  const std::vector<float>& depth;

  size_t index(int x, int y) const { return size_t(y) * size_t(width) + size_t(x); }
  bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
  bool hit(int x, int y) const { return std::isfinite(depth[index(x, y)]); }
  // What demodulation divides by (BT_DENOISE_ALBEDO_OFFSET).
  glm::vec3 demodulator(size_t i) const { return albedo[i] + BT_DENOISE_ALBEDO_OFFSET; }

  // |dz| to the nearer neighbour along each axis, the larger of the two axes: a surface's slope
  // in depth per pixel, not the jump to whatever lies beyond a silhouette.
  float depthGradient(int x, int y) const {
    const float z = depth[index(x, y)];
    const auto step = [&](int nx, int ny) { return !inside(nx, ny) || !hit(nx, ny) ? INFINITY : std::abs(depth[index(nx, ny)] - z); };
    const float gx = std::min(step(x - 1, y), step(x + 1, y));
    const float gy = std::min(step(x, y - 1), step(x, y + 1));
    return std::max(std::isfinite(gx) ? gx : 0.0f, std::isfinite(gy) ? gy : 0.0f);
  }

  // SVGF's normal stop between p and q.
  float normalWeight(size_t p, size_t q) const { return std::pow(std::max(0.0f, glm::dot(normal[p], normal[q])), BT_DENOISE_SIGMA_NORMAL); }

  // SVGF's normal and depth stops between p (at x, y) and q, `offset` pixels apart (|dx| + |dy|).
  // `own`: normalWeight(p, p), what every q of p's normal gets (the normals are the faces', so
  // most taps lie on p's plane): one pow a pixel instead of one a tap, the same floats.
  float geometryWeight(size_t p, size_t q, float gradient, float offset, float own) const {
    const float wNormal = normal[q] == normal[p] ? own : normalWeight(p, q);
    const float wDepth =
        std::exp(-std::abs(depth[p] - depth[q]) / (BT_DENOISE_SIGMA_DEPTH * gradient * offset + BT_DENOISE_DEPTH_FLOOR * depth[p]));
    return wNormal * wDepth;
  }
};

template <class RowFn> void forRows(int height, int threads, const RowFn& rows) {
  std::vector<std::thread> workers;
  const int rowsEach = (height + threads - 1) / threads;
  for (int t = 0; t < threads; ++t) {
    const int y0 = t * rowsEach, y1 = std::min(height, y0 + rowsEach);
    if (y0 < y1) workers.emplace_back([&rows, y0, y1] { rows(y0, y1); });
  }
  for (std::thread& w : workers) w.join();
}

// The variance of pixel (x, y)'s demodulated mean luminance from its neighbours (a young image,
// or none of its own second moment): the spread of the means over the window, the samples of
// one surface weighed by the normal and depth stops.
float spatialVariance(const Guide& g, const Pixels& in, int x, int y) {
  const size_t p = g.index(x, y);
  const float gradient = g.depthGradient(x, y), own = g.normalWeight(p, p);
  float weights = 0.0f, m1 = 0.0f, m2 = 0.0f;
  for (int dy = -BT_DENOISE_SPATIAL_VARIANCE_RADIUS; dy <= BT_DENOISE_SPATIAL_VARIANCE_RADIUS; ++dy)
    for (int dx = -BT_DENOISE_SPATIAL_VARIANCE_RADIUS; dx <= BT_DENOISE_SPATIAL_VARIANCE_RADIUS; ++dx) {
      const int qx = x + dx, qy = y + dy;
      if (!g.inside(qx, qy) || !g.hit(qx, qy)) continue;
      const size_t q = g.index(qx, qy);
      const float w = g.geometryWeight(p, q, gradient, float(std::abs(dx) + std::abs(dy)), own);
      const float l = luminance(glm::vec3(in[q]));
      weights += w, m1 += w * l, m2 += w * l * l;
    }
  m1 /= weights, m2 /= weights; // the centre's own weight is 1
  return std::max(0.0f, m2 - m1 * m1);
}

// The first step: the irradiance, and the variance of its luminance from the pixel's second
// moment (the beauty's luminance squared, scaled by the demodulation's ratio of luminances,
// exact where the noise has the mean's colour) or from its neighbours.
Pixels prepare(const Guide& g, const RenderImage& image, int threads) {
  const size_t n = image.beauty.size();
  Pixels out(n);
  for (size_t i = 0; i < n; ++i) {
    const glm::vec3 b = image.beauty[i];
    const bool finite = std::isfinite(b.x) && std::isfinite(b.y) && std::isfinite(b.z);
    out[i] = glm::vec4(!std::isfinite(image.depth[i]) ? b : finite ? b / g.demodulator(i) : glm::vec3(0.0f), 0.0f);
  }
  const int samples = std::max(image.samples, 1);
  const bool temporal = image.luminanceMoment2.size() == n && samples >= BT_DENOISE_TEMPORAL_VARIANCE_FROM;
  forRows(g.height, threads, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < g.width; ++x) {
        if (!g.hit(x, y)) continue;
        const size_t i = g.index(x, y);
        if (!temporal) {
          out[i].a = spatialVariance(g, out, x, y);
          continue;
        }
        const float beautyLuminance = luminance(image.beauty[i]), l = luminance(glm::vec3(out[i]));
        const float ratio = beautyLuminance > 0.0f ? l / beautyLuminance : 0.0f;
        const float variance = meanVariance(image.luminanceMoment2[i], beautyLuminance, samples) * ratio * ratio;
        out[i].a = std::isfinite(variance) ? variance : 0.0f;
      }
  });
  return out;
}

// The variance at (x, y) through a 3x3 Gaussian (its surface's pixels alone): the luminance
// stop's scale, steadier than one pixel's estimate.
float filteredVariance(const Guide& g, const Pixels& in, int x, int y) {
  float sum = 0.0f, weights = 0.0f;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int qx = x + dx, qy = y + dy;
      if (!g.inside(qx, qy) || !g.hit(qx, qy)) continue;
      const float w = kVarianceKernel[std::abs(dx)] * kVarianceKernel[std::abs(dy)];
      sum += w * in[g.index(qx, qy)].a, weights += w;
    }
  return sum / weights;
}

// One a-trous pass over rows [y0, y1): taps `spacing` pixels apart.
void filterRows(const Guide& g, const Pixels& in, Pixels& out, int spacing, int y0, int y1) {
  const float sigma = BT_DENOISE_SIGMA_LUMINANCE / float(spacing); // halved each pass
  for (int y = y0; y < y1; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const size_t p = g.index(x, y);
      if (!g.hit(x, y)) {
        out[p] = in[p];
        continue;
      }
      const float lp = luminance(glm::vec3(in[p])), gradient = g.depthGradient(x, y), own = g.normalWeight(p, p);
      const float lumScale = sigma * std::sqrt(filteredVariance(g, in, x, y)) + BT_DENOISE_LUMINANCE_FLOOR;
      glm::vec3 sum(0.0f);
      float weights = 0.0f, variance = 0.0f;
      for (int dy = -2; dy <= 2; ++dy) {
        for (int dx = -2; dx <= 2; ++dx) {
          const int qx = x + dx * spacing, qy = y + dy * spacing;
          if (!g.inside(qx, qy) || !g.hit(qx, qy)) continue;
          const size_t q = g.index(qx, qy);
          const float wLum = std::exp(-std::abs(lp - luminance(glm::vec3(in[q]))) / lumScale);
          const float w = kKernel[std::abs(dx)] * kKernel[std::abs(dy)] *
              g.geometryWeight(p, q, gradient, float(spacing * (std::abs(dx) + std::abs(dy))), own) * wLum;
          sum += w * glm::vec3(in[q]);
          variance += w * w * in[q].a;
          weights += w;
        }
      }
      out[p] = glm::vec4(sum / weights, variance / (weights * weights)); // the centre tap's weight is kKernel[0]^2 > 0
    }
  }
}

// The filtered pixel drawn back toward the raw mean where it moved by more than the pixel's own
// noise explains (BT_DENOISE_SHRINK_FROM), each channel on its own: `variance` is the mean's
// luminance's, a channel's taken as that scaled by the square of its share of the luminance
// (exact where the noise has the mean's colour, as prepare() assumes). Per channel rather than on
// the luminance, a change of hue the noise does not explain (a coloured texel's neighbours'
// irradiance) falls back too: lq_e4m3 at 64 / 128 / 256 spp 0.0217 / 0.0138 / 0.0086 against the
// luminance's 0.0235 / 0.0156 / 0.0106 (bench/README.md, issue 18 session 21).
glm::vec3 shrinkTowardRaw(const glm::vec3& raw, const glm::vec3& filtered, float variance) {
  const float rawLuminance = luminance(raw);
  glm::vec3 out;
  for (int c = 0; c < 3; ++c) {
    const float share = rawLuminance > 0.0f ? raw[c] / rawLuminance : 1.0f;
    const float channelVariance = variance * share * share, d = filtered[c] - raw[c];
    out[c] = raw[c] + d * (d * d > channelVariance ? channelVariance / (d * d) : 1.0f);
  }
  return out;
}

} // namespace

float meanVariance(float moment2, float meanLuminance, int samples) {
  const float variance = std::max(0.0f, moment2 - meanLuminance * meanLuminance) / float(samples - 1);
  return std::isfinite(variance) ? variance : 0.0f;
}

std::vector<glm::vec3> denoise(const RenderImage& image, int threads) {
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
  const Guide g{image.width, image.height, image.albedo, image.normal, image.depth};
  Pixels irradiance = prepare(g, image, threads), next(irradiance.size());
  for (int pass = 0; pass < BT_DENOISE_PASSES; ++pass) {
    forRows(g.height, threads, [&, pass](int y0, int y1) { filterRows(g, irradiance, next, 1 << pass, y0, y1); });
    std::swap(irradiance, next);
  }
  std::vector<glm::vec3> out(irradiance.size());
  const bool shrink = image.luminanceMoment2.size() == out.size() && image.samples >= BT_DENOISE_SHRINK_FROM;
  for (size_t i = 0; i < out.size(); ++i) {
    if (!std::isfinite(image.depth[i])) {
      out[i] = glm::vec3(irradiance[i]);
      continue;
    }
    out[i] = glm::vec3(irradiance[i]) * g.demodulator(i);
    const glm::vec3 raw = image.beauty[i];
    if (shrink && std::isfinite(raw.x + raw.y + raw.z))
      out[i] = shrinkTowardRaw(raw, out[i], meanVariance(image.luminanceMoment2[i], luminance(raw), image.samples));
  }
  return out;
}

} // namespace bt
