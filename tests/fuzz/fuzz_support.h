// What every harness shares: the bound on a scene worth preparing, and the preparation itself.
#pragma once

#include "lighting/render_scene.h"
#include "scene/scene.h"

#include <cstddef>

namespace bt::fuzz {

// A scene bigger than this is not prepared: building lights and the BVH of a few thousand faces
// already takes milliseconds under ASan, and the fuzzer wants thousands of runs a second.
// (Cost that grows with the input is the importers' to bound, see tests/fuzz/README.md.)
constexpr size_t kMaxPreparedFaces = 4096;

// The preparation every level goes through before a render: light entities -> lights, surface
// lights, emitters, the brush BVH (TraceScene::build). Faithful mode's bounce lights are left
// out: they trace the level and are bounded by their own budget (lighting/bounce.h).
inline void prepareForRender(const Scene& scene) {
  if (scene.faces.size() > kMaxPreparedFaces) return;
  RenderSceneOptions options;
  options.bounceLights = false;
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, options, diagnostics);
  (void)rs;
}

} // namespace bt::fuzz
