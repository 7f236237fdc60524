#include "lighting/lightmaps.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

namespace bt {

uint32_t lightmapFragmentAt(const Lightmaps& lm, uint32_t face, const glm::vec2& st) {
  const glm::uvec2 range = lm.faceRanges[face];
  uint32_t best = range.x;
  float bestOutside = -INFINITY;
  for (uint32_t f = range.x; f < range.x + range.y; ++f) {
    const GpuLightmapFragment& g = lm.fragments[f];
    float inside = INFINITY; // the smallest signed distance to an edge line, in texels
    for (uint32_t e = g.firstEdge; e < g.firstEdge + g.edgeCount; ++e) {
      const glm::vec4& l = lm.edges[e];
      inside = std::min(inside, l.x * st.x + l.y * st.y + l.z);
    }
    if (inside >= 0.0f) return f;
    if (inside > bestOutside) bestOutside = inside, best = f;
  }
  return best;
}

std::optional<glm::vec3> lightmapValue(const Lightmaps& lm, uint32_t face, const glm::vec2& st) {
  if (!lm.baked(face)) return std::nullopt;
  const GpuLightmapFragment& g = lm.fragments[lightmapFragmentAt(lm, face, st)];
  // Luxel (x, y) sits where u = x, v = y (texel 16 (min + x) on Quake's grid): the engine's
  // lightmap texture coordinates put the texel centres there, and its bilinear filter clamps at
  // the fragment's border.
  const float u = g.luxelU[0] * st.x + g.luxelU[1] * st.y + g.luxelU[2] - float(g.minS);
  const float v = g.luxelV[0] * st.x + g.luxelV[1] * st.y + g.luxelV[2] - float(g.minT);
  const float fu = std::floor(u), fv = std::floor(v);
  const float wu = u - fu, wv = v - fv;
  const int maxX = int(g.width) - 1, maxY = int(g.height) - 1;
  const int x0 = std::clamp(int(fu), 0, maxX), x1 = std::clamp(int(fu) + 1, 0, maxX);
  const int y0 = std::clamp(int(fv), 0, maxY), y1 = std::clamp(int(fv) + 1, 0, maxY);
  auto at = [&](int x, int y) {
    return shownLuxel(lm.luxelDisplay, unpackLuxel(lm.luxels[g.firstLuxel + uint32_t(y) * g.width + uint32_t(x)]));
  };
  const glm::vec3 top = at(x0, y0) * (1.0f - wu) + at(x1, y0) * wu;
  const glm::vec3 bottom = at(x0, y1) * (1.0f - wu) + at(x1, y1) * wu;
  return top * (1.0f - wv) + bottom * wv;
}

std::vector<uint32_t> packLightmaps(const Lightmaps& lm) {
  const uint32_t faceCount = lm.empty() ? 0u : uint32_t(lm.faceRanges.size());
  const uint32_t fragmentsAt = 8 + 2 * faceCount;
  const uint32_t edgesAt = fragmentsAt + uint32_t(lm.fragments.size()) * 16;
  const uint32_t luxelsAt = edgesAt + uint32_t(lm.edges.size()) * 4;
  const uint32_t tableAt = luxelsAt + uint32_t(lm.luxels.size());
  std::vector<uint32_t> out{fragmentsAt, edgesAt,         luxelsAt, faceCount, std::bit_cast<uint32_t>(lm.displayScale),
                            tableAt,     lm.luxelDisplay, 0u};
  out.reserve(tableAt + BT_LUXEL_TABLE_SIZE);
  for (uint32_t f = 0; f < faceCount; ++f) out.insert(out.end(), {lm.faceRanges[f].x, lm.faceRanges[f].y});
  auto bits = [](const float(&v)[4]) {
    return std::array<uint32_t, 4>{std::bit_cast<uint32_t>(v[0]), std::bit_cast<uint32_t>(v[1]), std::bit_cast<uint32_t>(v[2]), 0u};
  };
  for (const GpuLightmapFragment& g : lm.fragments) {
    out.insert(out.end(), {uint32_t(g.minS), uint32_t(g.minT), g.width, g.height, g.firstLuxel, g.firstEdge, g.edgeCount, 0u});
    for (const auto& axis : {bits(g.luxelU), bits(g.luxelV)}) out.insert(out.end(), axis.begin(), axis.end());
  }
  for (const glm::vec4& e : lm.edges)
    out.insert(out.end(), {std::bit_cast<uint32_t>(e.x), std::bit_cast<uint32_t>(e.y), std::bit_cast<uint32_t>(e.z), 0u});
  out.insert(out.end(), lm.luxels.begin(), lm.luxels.end());
  for (float v : goldSrcLuxelTable()) out.push_back(std::bit_cast<uint32_t>(v));
  return out;
}

} // namespace bt
