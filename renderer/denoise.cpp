#include "renderer/denoise.h"

#include "renderer/exposure.h" // luminance
#include "shaders/denoise_constants.glsl"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <thread>

namespace bt {

namespace {

constexpr float kKernel[3] = {BT_DENOISE_KERNEL0, BT_DENOISE_KERNEL1, BT_DENOISE_KERNEL2};

struct Guide {
  int width, height;
  const std::vector<glm::vec3>& albedo;
  const std::vector<glm::vec3>& normal;
  const std::vector<float>& depth;

  bool hit(int x, int y) const { return std::isfinite(depth[size_t(y) * size_t(width) + size_t(x)]); }
  glm::vec3 albedoFloor(size_t i) const { return glm::max(albedo[i], glm::vec3(BT_DENOISE_ALBEDO_FLOOR)); }

  // |dz| to the nearer neighbour along each axis, the larger of the two axes: a surface's slope
  // in depth per pixel, not the jump to whatever lies beyond a silhouette.
  float depthGradient(int x, int y) const {
    const float z = depth[size_t(y) * size_t(width) + size_t(x)];
    const auto step = [&](int nx, int ny) {
      if (nx < 0 || ny < 0 || nx >= width || ny >= height || !hit(nx, ny)) return INFINITY;
      return std::abs(depth[size_t(ny) * size_t(width) + size_t(nx)] - z);
    };
    const float gx = std::min(step(x - 1, y), step(x + 1, y));
    const float gy = std::min(step(x, y - 1), step(x, y + 1));
    const float g = std::max(std::isfinite(gx) ? gx : 0.0f, std::isfinite(gy) ? gy : 0.0f);
    return g;
  }
};

// One a-trous pass over rows [y0, y1): taps `spacing` pixels apart, luminance sigma `sigma`.
void filterRows(const Guide& g, const std::vector<glm::vec3>& in, std::vector<glm::vec3>& out, int spacing, float sigma, int y0, int y1) {
  for (int y = y0; y < y1; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const size_t p = size_t(y) * size_t(g.width) + size_t(x);
      if (!g.hit(x, y)) {
        out[p] = in[p];
        continue;
      }
      const glm::vec3 np = g.normal[p];
      const float zp = g.depth[p], lp = luminance(in[p]), gradient = g.depthGradient(x, y);
      glm::vec3 sum(0.0f);
      float weights = 0.0f;
      for (int dy = -2; dy <= 2; ++dy) {
        for (int dx = -2; dx <= 2; ++dx) {
          const int qx = x + dx * spacing, qy = y + dy * spacing;
          if (qx < 0 || qy < 0 || qx >= g.width || qy >= g.height || !g.hit(qx, qy)) continue;
          const size_t q = size_t(qy) * size_t(g.width) + size_t(qx);
          const float lq = luminance(in[q]);
          const float wNormal = std::pow(std::max(0.0f, glm::dot(np, g.normal[q])), BT_DENOISE_SIGMA_NORMAL);
          const float offset = float(spacing * (std::abs(dx) + std::abs(dy)));
          const float wDepth =
              std::exp(-std::abs(zp - g.depth[q]) / (BT_DENOISE_SIGMA_DEPTH * gradient * offset + BT_DENOISE_DEPTH_FLOOR * zp));
          const float wLum = std::exp(-std::abs(lp - lq) / (sigma * std::sqrt(std::max(lp * lq, 0.0f)) + BT_DENOISE_LUMINANCE_FLOOR));
          const float w = kKernel[std::abs(dx)] * kKernel[std::abs(dy)] * wNormal * wDepth * wLum;
          sum += w * in[q];
          weights += w;
        }
      }
      out[p] = sum / weights; // the centre tap's weight is kKernel[0]^2 > 0
    }
  }
}

void filterPass(const Guide& g, const std::vector<glm::vec3>& in, std::vector<glm::vec3>& out, int spacing, float sigma, int threads) {
  std::vector<std::thread> workers;
  const int rowsEach = (g.height + threads - 1) / threads;
  for (int t = 0; t < threads; ++t) {
    const int y0 = t * rowsEach, y1 = std::min(g.height, y0 + rowsEach);
    if (y0 < y1) workers.emplace_back([&, spacing, sigma, y0, y1] { filterRows(g, in, out, spacing, sigma, y0, y1); });
  }
  for (std::thread& w : workers) w.join();
}

} // namespace

std::vector<glm::vec3> denoise(const RenderImage& image, int threads) {
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
  const Guide g{image.width, image.height, image.albedo, image.normal, image.depth};
  const size_t n = image.beauty.size();
  std::vector<glm::vec3> irradiance(n), next(n);
  for (size_t i = 0; i < n; ++i) {
    const glm::vec3 b = image.beauty[i];
    const bool finite = std::isfinite(b.x) && std::isfinite(b.y) && std::isfinite(b.z);
    irradiance[i] = !std::isfinite(image.depth[i]) ? b : finite ? b / g.albedoFloor(i) : glm::vec3(0.0f);
  }
  float sigma = BT_DENOISE_SIGMA_LUMINANCE / std::sqrt(float(std::max(image.samples, 1)));
  for (int pass = 0; pass < BT_DENOISE_PASSES; ++pass, sigma *= 0.5f) {
    filterPass(g, irradiance, next, 1 << pass, sigma, threads);
    std::swap(irradiance, next);
  }
  for (size_t i = 0; i < n; ++i)
    if (std::isfinite(image.depth[i])) irradiance[i] *= g.albedoFloor(i);
  return irradiance;
}

} // namespace bt
