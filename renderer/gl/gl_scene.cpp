#include "renderer/gl/gl_scene.h"

#include "lighting/lightmaps.h"
#include "lighting/physical_light.h"
#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_tracer.h"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cstring>
#include <span>

namespace bt::gl {

namespace {

template <typename T> void upload(GLuint buffer, std::span<const T> v) {
  // A zero-sized buffer cannot be bound as an SSBO; an empty array uploads one zero element.
  const T zero{};
  const T* data = v.empty() ? &zero : v.data();
  const size_t bytes = std::max<size_t>(v.size(), 1) * sizeof(T);
  BT_GL(glNamedBufferStorage(buffer, static_cast<GLsizeiptr>(bytes), data, 0));
}

// A GlBvhNode child reference to TraceScene node n: a leaf's brush range, or the GlBvhNode that
// interior node n became (glIndex).
uint32_t childRef(const GpuBvhNode& n, uint32_t glIndex) {
  if (n.count == 0) return glIndex;
  if (n.count > kGlLeafMaxCount || n.leftFirst > kGlLeafMaxFirst)
    throw GlError(fmt::format("scene too large for the GL tracer: a BVH leaf of {} brushes from brush {} (at most {} from {})", n.count,
                              n.leftFirst, kGlLeafMaxCount, kGlLeafMaxFirst));
  return kGlLeafRef | n.count << 24 | n.leftFirst;
}

void setChild(float (&min)[3], float (&max)[3], uint32_t& ref, const GpuBvhNode& n, uint32_t glIndex) {
  std::copy(std::begin(n.boundsMin), std::end(n.boundsMin), min);
  std::copy(std::begin(n.boundsMax), std::end(n.boundsMax), max);
  ref = childRef(n, glIndex);
}

} // namespace

// Two linear passes: number the interior nodes in tree order (so the root stays 0), then give
// each its children's boxes and references.
std::vector<GlBvhNode> bvhForGl(std::span<const GpuBvhNode> nodes) {
  constexpr GlBvhNode kNoChildren{{0, 0, 0}, kGlNoChild, {0, 0, 0}, 0, {0, 0, 0}, kGlNoChild, {0, 0, 0}, 0};
  std::vector<GlBvhNode> gl;
  if (nodes.empty()) return {kNoChildren};
  if (nodes[0].count > 0) { // the whole scene is one leaf: the root's left child
    gl.push_back(kNoChildren);
    setChild(gl[0].leftMin, gl[0].leftMax, gl[0].left, nodes[0], 0);
    return gl;
  }
  std::vector<uint32_t> glIndex(nodes.size(), 0);
  uint32_t interior = 0;
  for (size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].count == 0) glIndex[i] = interior++;
  gl.resize(interior);
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].count != 0) continue;
    GlBvhNode& g = gl[glIndex[i]];
    const uint32_t l = nodes[i].leftFirst, r = l + 1;
    setChild(g.leftMin, g.leftMax, g.left, nodes[l], glIndex[l]);
    setChild(g.rightMin, g.rightMax, g.right, nodes[r], glIndex[r]);
  }
  return gl;
}

std::vector<GlBvhNode> sceneBvhForGl(const TraceScene& tracer) {
  std::vector<GlBvhNode> nodes = bvhForGl(tracer.nodes());
  if (tracer.triangleNodes().empty()) return nodes;
  const auto base = static_cast<uint32_t>(nodes.size());
  for (GlBvhNode node : bvhForGl(tracer.triangleNodes())) {
    for (uint32_t* ref : {&node.left, &node.right})
      if (*ref != kGlNoChild && !(*ref & kGlLeafRef)) *ref += base;
    nodes.push_back(node);
  }
  nodes[0].pad0 = base;
  nodes[0].pad1 = static_cast<uint32_t>(tracer.brushes().size_bytes() / 16);
  return nodes;
}

namespace {

// The brushes' rows, then the triangles' (gl_structs.h GlBvhNode). A brush of
// RenderScene::blocksFromInside gets the channel bits in its pad word (GpuBrush::pad, zero in the
// TraceScene): shaders/trace.glsl blocksFromInside ANDs it with a shadow ray's pass word, which
// has channel bits in faithful mode only.
std::vector<uint32_t> brushAndTriangleRows(const TraceScene& tracer, const std::vector<uint8_t>& blocksFromInside) {
  std::vector<uint32_t> words(tracer.brushes().size_bytes() / 4 + tracer.triangles().size_bytes() / 4);
  std::memcpy(words.data(), tracer.brushes().data(), tracer.brushes().size_bytes());
  constexpr size_t kPadWord = offsetof(GpuBrush, pad) / 4, kBrushWords = sizeof(GpuBrush) / 4;
  for (size_t slot = 0; slot < blocksFromInside.size() && slot < tracer.brushes().size(); ++slot)
    if (blocksFromInside[slot]) words[slot * kBrushWords + kPadWord] = BT_FACE_CHANNEL_BITS;
  if (!tracer.triangles().empty())
    std::memcpy(words.data() + tracer.brushes().size_bytes() / 4, tracer.triangles().data(), tracer.triangles().size_bytes());
  return words;
}

// The faces as TraceScene built them, a Quake 2 glass face's alpha (RenderScene::glassAlpha) in
// its pad word (GpuFace::pad), as a float's bits; zero, as TraceScene leaves it, on every other
// face, which shaders/textures.glsl glassAlpha reads as no glass.
std::vector<GpuFace> facesWithGlass(const TraceScene& tracer, const std::vector<float>& glassAlpha) {
  std::vector<GpuFace> faces(tracer.faces().begin(), tracer.faces().end());
  for (size_t f = 0; f < glassAlpha.size() && f < faces.size(); ++f)
    if (glassAlpha[f] < 1.0f) faces[f].pad = std::bit_cast<uint32_t>(glassAlpha[f]);
  return faces;
}

// A buffer texture over `buffer` (of `bytes` bytes) with texels of `format` (`texelBytes` each),
// on unit `unit`'s slot in `views`. The texel count must fit the context's buffer-texture limit
// (at least 65536 texels by the GL spec, 2^27 on NVIDIA and llvmpipe).
void makeTexelView(GLuint& view, GLuint buffer, GLenum format, size_t bytes, size_t texelBytes, const char* what) {
  GLint maxTexels = 0;
  BT_GL(glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels));
  const size_t texels = std::max<size_t>(bytes, texelBytes) / texelBytes;
  if (texels > static_cast<size_t>(maxTexels))
    throw GlError(
        fmt::format("scene too large for this GL context: {} needs {} buffer-texture texels, the limit is {}", what, texels, maxTexels));
  BT_GL(glCreateTextures(GL_TEXTURE_BUFFER, 1, &view));
  BT_GL(glTextureBuffer(view, format, buffer));
}

} // namespace

GlSceneBuffers::GlSceneBuffers(const TraceScene& tracer, const std::vector<GlMaterial>& materials, const GlLighting& lighting,
                               size_t materialCount) {
  BT_GL(glCreateBuffers(kBufferCount, buffers_));
  const std::vector<GlBvhNode> bvh = sceneBvhForGl(tracer);
  upload(buffers_[kBindingNodes], std::span<const GlBvhNode>(bvh));
  const std::vector<uint32_t> brushRows = brushAndTriangleRows(tracer, lighting.blocksFromInside);
  upload(buffers_[kBindingBrushes], std::span<const uint32_t>(brushRows));
  upload(buffers_[kBindingSides], tracer.sides());
  const std::vector<GpuFace> faces = facesWithGlass(tracer, lighting.glassAlpha);
  upload(buffers_[kBindingFaces], std::span<const GpuFace>(faces));
  GLint units = 0;
  BT_GL(glGetIntegerv(GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS, &units));
  if (units < static_cast<GLint>(kTextureUnitCount))
    throw GlError(fmt::format("the GL context offers {} compute texture units; the tracer needs {}", units, int(kTextureUnitCount)));
  makeTexelView(texelViews_[kTexelNodes - kTexelNodes], buffers_[kBindingNodes], GL_RGBA32UI, bvh.size() * sizeof(GlBvhNode), 16,
                "the BVH nodes");
  makeTexelView(texelViews_[kTexelBrushes - kTexelNodes], buffers_[kBindingBrushes], GL_RGBA32UI, brushRows.size() * 4, 16,
                "the brushes and triangles");
  makeTexelView(texelViews_[kTexelSides - kTexelNodes], buffers_[kBindingSides], GL_R32UI, tracer.sides().size_bytes(), 4,
                "the slanted sides");
  makeTexelView(texelViews_[kTexelFaces - kTexelNodes], buffers_[kBindingFaces], GL_RGBA32F, tracer.faces().size_bytes(), 16, "the faces");
  std::vector<uint32_t> faceFlags = lighting.faceFlags;
  faceFlags.resize(tracer.faces().size(), gpuFaceWord(0u, kDefaultChannels));
  faceFlags.insert(faceFlags.end(), lighting.liquidCsg.begin(), lighting.liquidCsg.end()); // gl_lighting.h liquidCsgTable
  upload(buffers_[kBindingFaceFlags], std::span<const uint32_t>(faceFlags));
  upload(buffers_[kBindingMaterials], std::span<const GlMaterial>(materials));
  materialCount_ = materialCount;
  uploadSurfaceLights(lighting.surfaceLights);
  upload(buffers_[kBindingEmitters], std::span<const GpuEmitter>(lighting.emitters));
  // A lighting without a grid (tests that list lights by hand) gets one built here.
  uploadLights(lighting.lights,
               lighting.lightGrid.cells.empty() ? buildLightGrid(lighting.lights, tracer.bounds(), lighting.scaledist) : lighting.lightGrid,
               lighting.scaledist);
  setLightmaps(lighting.lightmaps);
  uploadSky(lighting.sky);
}

void GlSceneBuffers::uploadLights(const std::vector<GpuLight>& lights, const LightGrid& grid, float scaledist) {
  // buildRenderScene prepares its lights' physical terms, each Quake light matched where its
  // light lands (lighting/physical_reference.h), which only the level's rays can say: those are kept.
  // Lights listed by hand (tests, tool authors) get matchDistance()'s rule here; a light is
  // unprepared while its hue sum is 0 (prepare gives 1 to 3 to any colour; a black light emits
  // nothing whatever its intensity).
  std::vector<GpuLight> prepared = lights;
  for (GpuLight& l : prepared)
    if (l.physicalHueSum == 0.0f) physical::prepare(l, scaledist);
  upload(buffers_[kBindingLights], std::span<const GpuLight>(prepared));
  // Light selection: the grid header and its cells in one buffer, as light_select.glsl reads them.
  const auto* header = reinterpret_cast<const uint8_t*>(&grid.header);
  const auto* cells = reinterpret_cast<const uint8_t*>(grid.cells.data());
  std::vector<uint8_t> gridBytes(header, header + sizeof(GpuLightGrid));
  gridBytes.insert(gridBytes.end(), cells, cells + grid.cells.size() * sizeof(GpuLightCell));
  upload(buffers_[kBindingLightGrid], std::span<const uint8_t>(gridBytes));
  upload(buffers_[kBindingLightIndices], std::span<const uint32_t>(grid.indices));
}

void GlSceneBuffers::uploadSurfaceLights(const std::vector<GpuLight>& templates) {
  // One template per material, so the shader indexes it by a face's material; value 0 = none.
  std::vector<GpuLight> surfaceLights = templates;
  surfaceLights.resize(std::max(surfaceLights.size(), materialCount_), GpuLight{.value = 0.0f});
  upload(buffers_[kBindingSurfaceLights], std::span<const GpuLight>(surfaceLights));
}

void GlSceneBuffers::setSurfaceLights(const std::vector<GpuLight>& surfaceLights) {
  BT_GL(glDeleteBuffers(1, &buffers_[kBindingSurfaceLights]));
  BT_GL(glCreateBuffers(1, &buffers_[kBindingSurfaceLights]));
  uploadSurfaceLights(surfaceLights);
}

void GlSceneBuffers::setLights(const std::vector<GpuLight>& lights, const LightGrid& grid, float scaledist) {
  // Buffer storage is immutable: new lights get new buffers, which bind() binds.
  for (const int binding : {kBindingLights, kBindingLightGrid, kBindingLightIndices}) {
    BT_GL(glDeleteBuffers(1, &buffers_[binding]));
    BT_GL(glCreateBuffers(1, &buffers_[binding]));
  }
  uploadLights(lights, grid, scaledist);
}

// The sky by direction as the CPU baked it (lighting/sky.h SkyMap): six layers of half floats,
// read with texelFetch only. A level without sky images gets one texel, never read.
void GlSceneBuffers::uploadSky(const SkyMap& sky) {
  const GLsizei size = std::max(sky.size, 1), layers = sky.size > 0 ? 6 : 1;
  BT_GL(glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &sky_));
  BT_GL(glTextureStorage3D(sky_, 1, GL_RGBA16F, size, size, layers));
  BT_GL(glTextureParameteri(sky_, GL_TEXTURE_MIN_FILTER, GL_NEAREST));
  BT_GL(glTextureParameteri(sky_, GL_TEXTURE_MAG_FILTER, GL_NEAREST));
  if (sky.size > 0) BT_GL(glTextureSubImage3D(sky_, 0, 0, 0, 0, size, size, layers, GL_RGBA, GL_HALF_FLOAT, sky.texels.data()));
}

void GlSceneBuffers::setLightmaps(const std::vector<uint32_t>& packed) {
  // Buffer storage is immutable: a new bake gets a new buffer. A level without baked luxels
  // still gets the header (no face), so the shader reads 0 faces, and GoldSrc's luxel table,
  // which the view at each pixel's point reads (lighting/luxel_display.h).
  static const std::vector<uint32_t> none = packLightmaps(Lightmaps{}); // a constant
  if (lightmaps_) BT_GL(glDeleteBuffers(1, &lightmaps_));
  BT_GL(glCreateBuffers(1, &lightmaps_));
  upload(lightmaps_, std::span<const uint32_t>(packed.size() < 8 ? none : packed));
}

GlSceneBuffers::~GlSceneBuffers() {
  glDeleteTextures(kTexelViewCount, texelViews_);
  glDeleteBuffers(kBufferCount, buffers_);
  glDeleteBuffers(1, &lightmaps_);
  glDeleteTextures(1, &sky_);
}

void GlSceneBuffers::bind() const {
  for (GLuint i = 0; i < kBufferCount; ++i) BT_GL(glBindBufferBase(GL_SHADER_STORAGE_BUFFER, i, buffers_[i]));
  BT_GL(glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBindingLightmaps, lightmaps_));
  for (GLuint i = 0; i < kTexelViewCount; ++i) BT_GL(glBindTextureUnit(kTexelNodes + i, texelViews_[i]));
  BT_GL(glBindTextureUnit(kTextureSky, sky_));
}

} // namespace bt::gl
