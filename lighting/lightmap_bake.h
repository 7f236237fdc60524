// Faithful mode's light compiler: the luxels ericw-tools `light` (2.0.0-alpha11, ltface.cc)
// computes for the faces qbsp makes, in the layout of lightmaps.h.
//
//   layout   each lit brush side becomes the faces qbsp compiles of it (surface_lights.h
//            compiledFacePolygons: CSG, the split and merge of qbsp's tree, the 240-texel
//            subdivision); each gets Quake's luxel grid: its texture-space extents in float,
//            floored / ceiled to 16 texels, one luxel every 16 texels (CalcSurfaceExtents);
//            with `_world_units_per_luxel` the compiler's decoupled grid instead (axes of the
//            face's snapped normal, a luxel every so many world units: lighting/README.md).
//   samples  CalcPoints: a luxel's point on the plane, lifted 1 unit off it. Inside the face it
//            stays; outside, it is snapped onto the face's boundary (then lifted) when that is
//            at most one luxel (of its grid) away, otherwise it is occluded. A point inside a solid brush, or
//            within 0.1 unit of one (Light_PointInSolid), is tried at the 8 corners of a 1-unit
//            cube around it, the void outside the level counting as solid; if all are solid it
//            is occluded. An occluded luxel gets only the floors (minlight). With `extra` N the
//            luxel is the mean of N x N such points on a grid 1/N luxel apart (-extra, -extra4).
//   light    at each point the faithful light sum of faithful_light.h (every light the grid lists,
//            each bounce light shadow-tested); a sky dome as the compiler's own 65 suns
//            (faithful.h skyDomeDirections); a sun's penumbra as the compiler's own directions
//            (penumbra_suns.h), `_deviance` copies averaged over `samples` random positions.
//   stored   light × _range, a coloured sum scaled so its brightest channel fits in 255,
//            truncated to whole bytes as the compiler writes them.
#pragma once

#include "lighting/faithful_light.h"
#include "lighting/lightmaps.h"
#include "lighting/qbsp_faces.h"
#include "lighting/render_scene.h"

#include <optional>
#include <span>

namespace bt {

struct LightmapBakeOptions {
  int extra = 1;           // sample points per luxel along each axis: 1 (the compiler's default), 2 or 4
  int samples = 0;         // samples of each soft light per point; 0: 1 for a level without soft lights, else 64
  unsigned threads = 0;    // 0: all cores
  bool shadowCache = true; // faithful_light.h ShadowCache: off only to measure it or to test that it changes nothing
};

// Whether the compiled level gives scene face `face` a lightmap: drawn, not sky, and a liquid
// only with `_litwater`.
bool faceHasLightmap(const RenderScene& rs, uint32_t face);

// The lightmap layout of `faces` (scene face indices; those without a lightmap are skipped),
// luxels zero.
Lightmaps layoutLightmaps(const RenderScene& rs, std::span<const uint32_t> faces, unsigned threads = 0);
// ... of every face that has one.
Lightmaps layoutLightmaps(const RenderScene& rs, unsigned threads = 0);

// Where the compiler samples each luxel of `lightmaps` (extra x extra points each, luxel-major:
// scene/gpu_structs.h GpuLuxelSample), what both tracers' bakes light.
std::vector<GpuLuxelSample> luxelSamples(const RenderScene& rs, const Lightmaps& lightmaps, int extra, unsigned threads = 0);

// Where the compiler samples a point 1 unit off scene face `face` (`point`, on its compiled face
// or pulled onto it): itself, unless it lies in a solid (or within 0.1 unit of one), in which case
// the first of the 8 corners of a 1-unit cube around it that lies outside them
// (PositionSamplePointOnFace); nullopt (occluded, no light) when all are solid. `voids`: the
// level's void test (the world's void counts as solid for a face on the default channel).
std::optional<glm::vec3> compilerSamplePoint(const RenderScene& rs, const std::vector<BrushContents>& contents, const VoidTest& voids,
                                             uint32_t face, const dvec3& point);

// A bake as both tracers run it: the sample points, and the passes of faithful_light.h
// faithfulLuxelPass over them, pass k of sample i drawing from pixelRng(i, k, 0, seed).
struct LuxelBakeJob {
  std::vector<GpuLuxelSample> samples;
  uint32_t samplesPerLuxel = 1; // extra^2
  int softSamples = 1;
  int passes = 1;
  uint32_t seed = 0;
  std::vector<glm::vec3> sunTable; // RenderScene::sunTable, which the GPU bake uploads
  // The compiler's light cull without vis data (vis_approx.h), where the level has it: where each
  // culled light stands and its box (by GpuLight::visBox - 1; RenderScene::visBoxLights and
  // visBoxes), and each compiled face's box (by fragment, a sample's flags >>
  // kLuxelSampleBoxShift), which the GPU bake uploads after the sun table. lightBoxes is empty
  // where the RenderScene left them to the GPU (RenderSceneOptions::VisBoxes::Gpu): the GL bake
  // computes them, the CPU's bakes compute them as they start (withLightBoxes).
  std::vector<glm::vec3> boxedLights;
  std::vector<GpuVisBox> lightBoxes;
  std::vector<GpuVisBox> receiverBoxes;
  VisCull cull(const GpuLuxelSample& s) const {
    const uint32_t box = s.flags >> kLuxelSampleBoxShift;
    if (!box || box > receiverBoxes.size() || lightBoxes.size() != boxedLights.size()) return {};
    return {&receiverBoxes[box - 1], lightBoxes.data()};
  }
};
LuxelBakeJob luxelBakeJob(const RenderScene& rs, const Lightmaps& lightmaps, const LightmapBakeOptions& options = {});

// Every luxel of `lightmaps`, as above. The same result for any number of threads.
void bakeLightmaps(const RenderScene& rs, Lightmaps& lightmaps, const LightmapBakeOptions& options = {});

// The luxels of `lightmaps` one set per light style, as the compiler keeps a lightmap per style
// of a face and the engine sums them each frame weighted by the lightstyle's value
// (R_BuildLightMap; compiled_lightmaps.h engineLuxel): the viewer's style sliders re-sum them
// (sumStyles) instead of baking again. Each set holds the luxel's light before the store (light x
// _range, in float): the floors (minlight, a face's template minlight, `_ambient`) in style 0's
// alone, as the compiler puts them; each other style's lights alone, negative ones taken off.
// Every set covers every luxel (no 4-style limit per face).
struct StyledLuxels {
  std::vector<int> styles;                   // 0, then the level's other styles, increasing
  std::vector<std::vector<glm::vec3>> light; // per style of `styles`, per luxel
};
// The light styles of rs.lights other than 0, increasing.
std::vector<int> lightStylesOf(const RenderScene& rs);
StyledLuxels bakeStyledLuxels(const RenderScene& rs, const Lightmaps& lightmaps, const LightmapBakeOptions& options = {});
// The luxels shown with each style's light times weights[style], stored as bakeLightmaps stores
// one: with every weight 1 (and no floor beside a light of another style) the luxels bakeLightmaps
// gives, with weight w for a style those of a level whose lights of that style are w times as
// bright (LightOptions::styleScale), up to float rounding before the truncation to bytes.
std::vector<uint32_t> sumStyles(const StyledLuxels& styled, std::span<const float, 256> weights);

} // namespace bt
