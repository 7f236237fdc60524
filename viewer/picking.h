// A click on the image: the face under the cursor and where it comes from, so that a mapper finds
// it in the editor (the .map's file:line of the face and of its brush), with its texture, its
// entity and what the compiler makes of it (sky, liquid, Quake 2/3 contents), and why the point
// is lit: the light there broken down by light, faithful mode's (faithfulLightShares) or physical
// mode's (physicalLightShares).
#pragma once

#include "lighting/render_scene.h"
#include "renderer/camera.h"
#include "renderer/render.h" // IntegratorSettings

#include <string>
#include <vector>

namespace bt {

struct PickedFace {
  bool hit = false;
  std::string fileLine;           // "<file>:<line>" of the face ("" for a compiled level)
  std::vector<std::string> lines; // what the panel shows
};

// The face seen through point (x, y) of a width x height image from `pose` (pixels, top left 0 0),
// its light broken down in `lighting`'s mode (physical: with its bounces and firefly clamp).
PickedFace pickFace(const RenderScene& rs, const CameraPose& pose, int width, int height, float x, float y,
                    const IntegratorSettings& lighting = {});

} // namespace bt
