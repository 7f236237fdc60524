// The GL compute tracer: a Scene uploaded once, images rendered from a camera.
#pragma once

#include "bvh/trace_scene.h"
#include "lighting/light_grid.h"
#include "lighting/lights.h"
#include "lighting/sky.h"
#include "renderer/gl/gl_camera.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_structs.h"
#include "renderer/gl/gl_tracer_programs.h"
#include "scene/scene.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace bt::gl {

// Per pixel, rows top to bottom, with the CPU reference's meanings (renderer/render.h RenderImage).
// A pixel that sees nothing has albedo 0, normal 0, depth +infinity and face kNothingHit (not
// bt::kNoFace: this image counts faces from 1).
struct AovImages {
  static constexpr uint32_t kNothingHit = 0;
  int width = 0;
  int height = 0;
  std::vector<glm::vec4> albedo; // linear rgb, a = 1 where something was hit
  std::vector<glm::vec3> normal; // world-space geometric normal (the face plane's; facing the ray for a liquid seen from inside)
  std::vector<float> depth;      // distance along the ray
  std::vector<uint32_t> face;    // index into Scene::faces + 1
};

// What the integrator needs beyond geometry and textures: lighting/render_scene.h's classification of
// faces and materials, its light list and emitters, and the worldspawn lighting keys. The
// render command fills it from lighting/render_scene.h's RenderScene, so both tracers light alike.
struct GlLighting {
  std::vector<uint32_t> faceFlags; // per Scene face: scene/gpu_structs.h gpuFaceWord (kFace* and channels); empty = none
  std::vector<uint32_t>
      materialFlags; // per material: kMaterialGgx / kMaterialHasEmissive / kMaterialBlendAddGl / kMaterialBlendFilterGl overrides; empty = from the images
  std::vector<float> materialOpacity;    // per material: GpuMaterial::opacity (liquids); empty = opaque
  std::vector<glm::vec4> materialLiquid; // per material: GlMaterial::liquid (physical tint, opacity); empty = opaque
  std::vector<GpuLight> lights;          // point lights, suns, domes
  LightGrid lightGrid;                   // lighting/light_grid.h's lists over `lights`; no cells = built on upload
  std::vector<GpuLight> surfaceLights;   // per material: its _surface template (value 0 = none); empty = none
  std::vector<GpuEmitter> emitters;      // triangles of emitting faces, cdf by area
  float emitterArea = 0.0f;
  glm::vec3 minlight{0.0f};
  glm::vec3 ambient{0.0f};      // q3map2's `_ambient` (WorldLighting::ambient)
  float range = 0.5f;           // _range
  float overbrightOne = 128.0f; // WorldLighting::overbrightOne: what the per-pixel view divides by
  uint32_t luxelDisplay = 0;    // WorldLighting::luxelDisplay: the per-pixel view's luxel table
  float scaledist = 1.0f;       // _dist
  float bouncescale = 1.0f;
  int faithfulBounces = 0; // _bounce
  bool litwater = false;
  SkyMap sky;                      // RenderScene::sky: the level's sky by direction (size 0: none)
  DirtSettings dirt;               // worldspawn dirt; enabled builds the faithful program with BT_FAITHFUL_DIRT
  LightKinds lightKinds;           // RenderScene::lightKinds: which faithful program the level was started with
  std::vector<uint32_t> lightmaps; // RenderScene::lightmaps packed (lighting/lightmaps.h packLightmaps); empty = none
  // RenderScene::liquidCsg as shaders/visible.glsl reads it after the face flags (liquidCsgTable
  // in gl_lighting.h); empty for a level without overlapping liquids, whose programs are built
  // without the rule (FaithfulFeatures::liquidCsg).
  std::vector<uint32_t> liquidCsg;
  // RenderScene::blocksFromInside, per TraceScene brush slot: written into the brushes' pad words
  // (gl_scene.cpp) for shaders/trace.glsl; empty for a level without such brushes, whose
  // programs are built without the rule (FaithfulFeatures::blocksFromInside).
  std::vector<uint8_t> blocksFromInside;
  // RenderScene::glassAlpha, per scene face: written into the faces' pad words (gl_scene.cpp) for
  // the faithful path tracer; empty for a level without Quake 2 glass, whose programs are built
  // without it (FaithfulFeatures::glass).
  std::vector<float> glassAlpha;
};

// The parts of a level's faithful programs (and the liquid CSG, which physical ones take too):
// its LightKinds', what its lights need, and its LevelParts (the liquid CSG, the rule from
// inside, Quake 2's glass), and whether its lightmaps show a baked face (FaithfulFeatures::luxels).
FaithfulFeatures faithfulFeatures(const GlLighting& lighting);
// Whether luxels packed by packLightmaps (GlLighting::lightmaps) show any face: not for the
// header alone (none), nor for a layout of faces none of which is baked.
bool showsLuxels(const std::vector<uint32_t>& packed);

struct BeautySettings {
  int width = 640;
  int height = 360;
  int spp = 16;
  uint32_t seed = 0;
  bool physical = false;      // --lighting physical
  int bounces = 3;            // physical mode
  float clampIndirect = 0.0f; // physical mode's firefly clamp (IntegratorSettings::clampIndirect)
  PathTracerForm form = PathTracerForm::Auto;
};

// Mean linear radiance per pixel, rows top to bottom.
struct BeautyImage {
  int width = 0;
  int height = 0;
  int samples = 0;
  int wavefrontSamples = 0; // of `samples`, those the wavefront kernels drew
  std::vector<glm::vec3> beauty;
  std::vector<float> luminanceMoment2; // RenderImage::luminanceMoment2 (the sum's alpha / samples)
};

// A rectangle of an image's pixels, x to the right and y down from the top-left pixel.
struct PixelRect {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;
  size_t pixels() const { return size_t(std::max(width, 0)) * size_t(std::max(height, 0)); }
};

// The path tracer's work group side (local_size of pathtrace.comp and wavefront_trace.comp,
// checked against the programs where a piece is drawn): a piece of a sample starts at a multiple
// of it, and ends at one or at the image's edge, so that its groups cover it and no pixel beside.
constexpr int kPieceAlignment = 8;

struct RayBenchmark {
  size_t primaryRays = 0; // per pass
  size_t bounceRays = 0;  // per pass: one for each primary ray that hit something
  int passes = 0;
  double primarySeconds = 0.0; // all passes
  double bounceSeconds = 0.0;
  // The bounce rays again as shadow rays (any hit) of at most shadowLength: the median distance
  // to the bounce rays' hits, so that about half of them are blocked.
  float shadowLength = 0.0f;
  double shadowSeconds = 0.0;
  // FNV-1a of the last pass's results: the primary hits, the bounce rays' t, and that image
  // after the shadow rays (blocked ones negated), so that two traversals can be compared.
  uint64_t primaryHash = 0, bounceHash = 0, shadowHash = 0;
  // With RayBenchVariant's BT_RB_COUNT: per mode (primary, bounce, shadow), for each of
  // interior nodes visited, brush boxes tested, brushes whose planes were read, planes tested and
  // the deepest stack, the sum over the passes' rays and the largest (shaders/trace.glsl).
  std::array<uint32_t, 48> walkCounts{};
  bool counted = false;
  // With a variant: FNV-1a of bounceT after its last pass of each mode (the variant's own results).
  std::array<uint64_t, 3> variantHashes{};
};

// A measurement of part of the walk (issue 20): raybench.comp built with these #defines as well
// (its BT_RB_* switches) and timed in place of the plain program, which still makes the hits
// the bounce rays start from, the shadow rays' length and the hashes. Its program binary is
// written to `binaryPath` when that is set (the driver's code, to read its registers).
struct RayBenchVariant {
  std::vector<std::string> defines;
  std::string binaryPath;
};

struct ProgramBuild {
  double milliseconds = 0.0; // compile and link (or load) from the start of the build, and the driver's work at the first dispatch
  bool fromCache = false;
  // Of those, the empty dispatch after the link (buffers made, one group dispatched, glFinish),
  // and its calls before the glFinish.
  double dispatchMilliseconds = 0.0, dispatchCallsMilliseconds = 0.0;
};

class GlTracer {
public:
  // Uploads the scene: `tracer`'s BVH, brushes, sides and faces as they are (the CPU
  // reference's RenderScene::tracer, so both trace the same tree), the scene's textures and the
  // lighting. The context must stay current on this thread for the tracer's life.
  GlTracer(GlContext& context, const Scene& scene, const TraceScene& tracer, TextureMode textures, const GlLighting& lighting = {});
  // The same with programs built (or being built) already: their texture path is the tracer's.
  GlTracer(GlContext& context, const Scene& scene, const TraceScene& tracer, std::shared_ptr<TracerPrograms> programs,
           const GlLighting& lighting = {});
  // The same with a TraceScene built here with default options (every brush traceable).
  GlTracer(GlContext& context, const Scene& scene, TextureMode textures, const GlLighting& lighting = {});
  ~GlTracer();
  GlTracer(const GlTracer&) = delete;
  GlTracer& operator=(const GlTracer&) = delete;

  TextureMode textureMode() const; // the path in use: Bindless or Arrays
  // The parts of its faithful programs: the level's LightKinds' and what its lights need.
  FaithfulFeatures faithfulFeatures() const;

  // Where programs are cached; ProgramCache::fromEnvironment(GL_VENDOR) unless set before they
  // are built.
  void setProgramCache(ProgramCache cache);
  TracerPrograms& programs();
  // Builds the path tracer's program for one lighting mode (BeautySettings::physical) now, for
  // images of width x height (renderBeauty otherwise builds it on first use).
  ProgramBuild buildPathTracer(int width, int height, bool physical);
  // The same for the wavefront form's two kernels.
  ProgramBuild buildWavefront(int width, int height, bool physical);

  AovImages renderAovs(const CameraBasis& camera, int width, int height);

  // settings.spp samples per pixel, summed in an RGBA32F image: one dispatch each with the
  // megakernel, or rounds of trace and shade dispatches with the wavefront kernels (settings.form
  // picks; Auto switches to the megakernel at the first sample after its compile ends).
  // progress(n) is called after every sample with the samples done; returning false stops
  // early (--time).
  BeautyImage renderBeauty(const CameraBasis& camera, const BeautySettings& settings, const std::function<bool(int)>& progress = {});

  // One sample of a progressive render into `sum`, an RGBA32F texture of settings.width by
  // settings.height that the caller keeps across calls (settings.spp is ignored): sample
  // `sampleIndex` draws renderBeauty's stream for its sample n, so sampleIndex 0 overwrites the
  // sum (pathtrace.comp `accumulate`) and later ones add to it. Nothing is read back: the
  // viewer tonemaps the sum on the GPU (gl_progressive.h).
  void addSample(const CameraBasis& camera, const BeautySettings& settings, unsigned sum, uint32_t sampleIndex);
  // The same for the pixels of `piece` only (kPieceAlignment says where it may start and end; it
  // is clipped to the image), one dispatch with the megakernel: a slow GL draws a sample in
  // pieces, the window answering between them (gl_progressive.h). Each pixel draws what the
  // whole sample would: the pieces of a sample sum to it, bit for bit. Throws GlError for a
  // piece that is not aligned.
  void addSample(const CameraBasis& camera, const BeautySettings& settings, unsigned sum, uint32_t sampleIndex, const PixelRect& piece);

  // Times closest-hit queries alone (shaders/raybench.comp): `passes` frames of primary rays,
  // then `passes` frames of one cosine bounce ray from each primary hit, then those bounce rays
  // as shadow rays (RayBenchmark::shadowLength says how long).
  RayBenchmark benchmarkRays(const CameraBasis& camera, int width, int height, int passes, const RayBenchVariant& variant = {});
  // Replaces faithful mode's baked luxels (GlLighting::lightmaps, packed; empty for none): a bake
  // made after the upload (gl_bench, a viewer that bakes as the camera moves).
  void setLightmaps(const std::vector<uint32_t>& packed);
  // Replaces the lights (GlLighting::lights, the same lights with other colours: the viewer's
  // style sliders) and their grid, built anew over them; `scaledist` as GlLighting's.
  void setLights(const std::vector<GpuLight>& lights, const LightGrid& grid, float scaledist);
  // Replaces the `_surface` templates (GlLighting::surfaceLights, the same with other colours).
  void setSurfaceLights(const std::vector<GpuLight>& surfaceLights);
  // For passes of other kernels over the level (gl_bake.h): binds the world block, the scene's
  // buffers and textures as the path tracer sees them; the lightmap buffer's GL name; and its
  // whole packed content, read back (tests).
  void bindLevel();
  unsigned lightmapBuffer() const;
  std::vector<uint32_t> readLightmaps() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace bt::gl
