// The luxels a render needs before a faithful image: those of the faces its camera can see, laid
// out and baked by lighting/lightmap_bake.h.
#pragma once

#include "lighting/lightmap_bake.h"
#include "renderer/camera.h"

#include <cstdint>
#include <vector>

namespace bt {

// The faces with a lightmap that a width x height image from `camera` can show: those hit by rays
// through every pixel's corners and centre, so that a render bakes only what its samples land on
// (a face seen by no such ray, a sliver under half a pixel, is lit at the point itself).
std::vector<uint32_t> facesSeen(const RenderScene& rs, const Camera& camera, int width, int height, unsigned threads = 0);

// The layout of the faces `camera` sees (all lit faces when camera is null), luxels zero: what a
// GPU bake fills.
Lightmaps layoutFaithfulLightmaps(const RenderScene& rs, const Camera* camera, int width, int height, unsigned threads = 0);

// What `render --backend cpu` does before a faithful image: lay out and bake the faces `camera` sees
// (all lit faces when camera is null) into rs.lightmaps.
void bakeFaithfulLightmaps(RenderScene& rs, const Camera* camera, int width, int height, const LightmapBakeOptions& options);

} // namespace bt
