// Faithful `_bounce`: ericw-tools `light`'s bounced light (light/bounce.cc, ltface.cc
// IndirectLightFace, at 2.0.0-alpha11), as point lights that both tracers sum like any other.
//
// After the direct pass the compiler turns every face that bounces into one light:
//   - the face's mean direct light L over its luxels (only the positive lights of style 0 and
//     the suns add to it, not minlight: ltface.cc's bounce_color over the sample count);
//   - emit = L x mix(127, the texture's mean colour, `_bouncecolorscale`) / 255;
//   - intensity = the brightest channel of emit; the colour is emit / intensity when that is
//     above 1, emit itself otherwise (so a dim face's colour is not normalised);
//   - one point (`-emissivequality low`, the default) at the face's vertex mean, 1 unit off it,
//     carrying intensity x area x `_bouncescale` x 0.5 (IndirectLightFace's "close-ish to the old
//     code" scale).
// A receiver gets colour x value x cos(emitting side) x cos(receiving side) / max(d, 128)^2,
// shadowed, dropped where no channel is above 0.01 (LightFormula::Bounce, faithful.h).
// `_bounce N` repeats this N times, each pass re-emitting only what the previous pass brought.
//
// Which faces bounce (Face_ShouldBounce): lit ones (not sky, not hidden, liquids only with
// `_litwater`) of models that cast shadows (the world, func_detail/func_group, `_shadow 1`),
// except `_surface` template faces and the brush entities with `_bounce -1`. The faces are the
// compiler's (surface_lights.h compiledFacePolygons; a side cut into more than 256 fragments keeps
// its fragments, see bounceFaces); the mean direct light is sampled on their luxel grid (16
// texels), each luxel placed as the compiler places it (CalcPointNormal: a luxel off the face
// lies on the coplanar bounce face across the edge it is behind, up to 3 faces on, else is
// snapped onto the face within a luxel or counted dark), and moved out of a solid it lies in (or
// counted dark) as the compiler moves it. A large level
// samples a subset of the luxels and merges the lights it makes (BounceBudget).
#pragma once

#include "lighting/render_scene.h"
#include "lighting/surface_lights.h"

#include <vector>

namespace bt {

// ericw-tools' grey for `_bouncecolorscale 0` and for a texture without pixels (127 of 255).
inline constexpr float kBounceGrey = 127.0f / 255.0f;
// IndirectLightFace scales bounce lights by `_bouncescale` x this.
inline constexpr float kBounceScale = 0.5f;

// One face that bounces light: a compiled face of scene face `face`.
struct BounceFace {
  uint32_t face = 0;
  std::vector<dvec3> polygon;
};

// The compiled faces of `scene` that bounce light (see above), in side order, made on `threads`
// threads (0: all cores; the same faces for any number). `contents` as render_scene.cpp
// classifies the brushes for qbsp's CSG.
std::vector<BounceFace> bounceFaces(const RenderScene& rs, const std::vector<BrushContents>& contents, unsigned threads = 0);

// The bounce light of one face whose mean source light is `meanLight` (light units, rgb) and
// whose texture's mean colour is `texture` (0..1, its own sRGB bytes), or nullopt when it emits
// nothing.
std::optional<GpuLight> bounceLight(const RenderScene& rs, const BounceFace& face, const glm::vec3& meanLight, const glm::vec3& texture);

// What the preparation may spend, so that a large level with `_bounce 3` prepares in seconds
// (a preview) while a small one stays exact. Each pass samples every luxel of every face while
// the level's luxels fit its budget, otherwise an evenly spread subset of each face's luxels (at
// least one) in proportion: the face's mean light is then an estimate. A later pass also casts at
// most `gatherShadowRays` per luxel, drawn among the previous pass's lights by their share there.
struct BounceBudget {
  size_t directLuxels = 65536; // per direct pass: the lit-oracle levels (up to 44 000) stay exact
  size_t gatherLuxels = 4096;  // per later pass: about one luxel per face on a large level
  size_t gatherShadowRays = 32;
  unsigned threads = 0; // 0: all cores (the result is the same for any number)
  // A bounce light reaches most of a level (its 0.01 gate at value / d^2), so every shaded point
  // shadow-tests nearly all of them: above this many, nearby faces' lights of one orientation
  // are merged (clusterBounceLights).
  size_t renderLights = 1024; // lq_e3m1: 24 590 -> 989; the lit-oracle levels (up to 356) keep theirs
  // A later pass's luxel sweeps only the previous pass's lights that can light it: those a light
  // grid of them (light_grid.h) lists for it, at most this many cells along its longest axis. The
  // result is bit for bit that of sweeping every light (0: no grid, the reference), only sooner.
  // Coarser than the renderer's 32: lq_e3m1's 7 000-9 000 lights reach most of the level, so a
  // finer grid lists hardly fewer a cell (32 cells: 2 400 a cell in 14 000 cells, the whole
  // preparation 0.4 s of CPU slower; 16: no faster) than this one (2 900 of 6 800, in 280 cells).
  uint32_t gatherGridCellsPerAxis = 8;
  // A luxel that several passes sample casts its `_dirtmode 0` dirt rays once (the same
  // occlusion: those rays draw no random numbers). false: each pass casts them (the reference).
  bool reuseDirtOcclusion = true;
};

struct BounceLights {
  std::vector<GpuLight> lights;
  size_t luxels = 0;          // the compiled faces' luxels (one pass)
  size_t sampledLuxels = 0;   // the fewest any pass sampled: == luxels when the bounce is exact
  bool sampledLights = false; // a later pass drew among the previous pass's lights
  size_t madeLights = 0;      // the bounce lights before clustering (== lights.size() when none)
  bool exact() const { return sampledLuxels == luxels && !sampledLights && madeLights == lights.size(); }
};

// At most `maxLights` lights standing for `lights` (bounce lights): those of one cell of a grid
// over `bounds` facing the same axis direction become one, at their power-weighted mean origin
// and normal, carrying their summed value x colour. The grid is the finest that fits. The result
// is `lights` itself when it fits.
std::vector<GpuLight> clusterBounceLights(const std::vector<GpuLight>& lights, const Bounds& bounds, size_t maxLights);

// Every pass of the level's `_bounce` (none when it is 0): `rs` holds the direct lights and
// their grid. The faces are sampled on all cores; the result does not depend on their number.
BounceLights makeBounceLights(const RenderScene& rs, const std::vector<BrushContents>& contents, const BounceBudget& budget = {});

// The luxels a pass samples of a face that has `count`, when the level has `total` and the pass
// may sample `budget`: all of them while the total fits, else count x budget / total rounded, at
// least one.
size_t bounceSampleCount(size_t count, size_t total, size_t budget);

} // namespace bt
