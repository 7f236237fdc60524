#include "renderer/view_lightmaps.h"

#include "lighting/liquids.h"
#include "lighting/visibility.h"
#include "scene/parallel_for.h"

#include <vector>

namespace bt {

std::vector<uint32_t> facesSeen(const RenderScene& rs, const Camera& camera, int width, int height, unsigned threads) {
  const size_t faceCount = rs.scene->faces.size();
  std::vector<std::vector<uint8_t>> seenByRow(size_t(2 * height + 1));
  parallelFor(seenByRow.size(), threads, [&](size_t row) {
    std::vector<uint8_t>& seen = seenByRow[row];
    seen.assign(faceCount, 0);
    for (int column = 0; column <= 2 * width; ++column) {
      // What lies behind a translucent liquid or Quake 2's glass shows too (render_scene.h engineBlend).
      Ray ray = camera.ray(0.5f * float(column), 0.5f * float(row));
      for (SurfaceHit hit = traceVisible(rs, ray); hit.found; hit = traceVisible(rs, ray)) {
        seen[hit.face] = 1;
        if (!(engineBlend(rs, hit.face).behind > 0.0f)) break;
        ray.tMin = continueRayAfter(hit.t);
      }
    }
  });
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < faceCount; ++f) {
    bool seen = false;
    for (const std::vector<uint8_t>& row : seenByRow) seen = seen || row[f];
    if (seen && faceHasLightmap(rs, f)) faces.push_back(f);
  }
  return faces;
}

Lightmaps layoutFaithfulLightmaps(const RenderScene& rs, const Camera* camera, int width, int height, unsigned threads) {
  return camera ? layoutLightmaps(rs, facesSeen(rs, *camera, width, height, threads), threads) : layoutLightmaps(rs, threads);
}

void bakeFaithfulLightmaps(RenderScene& rs, const Camera* camera, int width, int height, const LightmapBakeOptions& options) {
  rs.lightmaps = layoutFaithfulLightmaps(rs, camera, width, height, options.threads);
  bakeLightmaps(rs, rs.lightmaps, options);
}

} // namespace bt
