// What a ray sees of a prepared level under Quake's drawing rules: faces that are never drawn
// (hidden textures, back faces) are skipped, alpha-tested holes let rays through, and each
// lighting mode has its own idea of what casts a shadow. Both light models and the CPU tracer
// ask these questions; shaders/visible.glsl answers them the same way on the GPU.
#pragma once

#include "lighting/render_scene.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace bt {

enum class LightingMode { Faithful, Physical };

// A hit after skipping faces that are never drawn.
struct SurfaceHit {
  bool found = false;
  float t = 0.0f;
  uint32_t face = 0;
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f}; // the face plane's normal, facing the ray (flipped for a liquid face seen from inside)
};

SurfaceHit traceVisible(const RenderScene& rs, const Ray& ray);

// True when something that casts shadows in `mode` lies between the ray's tmin and tmax; in
// faithful mode only faces on one of `channels` (a light's `_shadow_channel_mask`) do, and a ray
// leaving a brush of RenderScene::blocksFromInside is blocked as one entering it. With
// `blocker`, a brush that blocked it is stored there (its TraceScene slot; unchanged when nothing,
// or a mesh triangle, did): what the next shadow ray toward the same light tries first.
bool occluded(const RenderScene& rs, const Ray& ray, LightingMode mode, uint32_t channels = kDefaultChannels, uint32_t* blocker = nullptr);

// Whether brush `slot` (a TraceScene slot) alone blocks the ray: the ray enters it within (tmin,
// tmax), from outside, through a face that blocks light in `mode` (on `channels`), where the face
// has no hole. One brush test. Where it says yes, occluded() says yes too, except where a face
// that does not block lies in exactly the plane the ray enters the brush by and wins the tie for
// that hit.
bool blockedByBrush(const RenderScene& rs, const Ray& ray, LightingMode mode, uint32_t slot, uint32_t channels = kDefaultChannels);

// occluded() and blockedByBrush() for `ray` prepared once as `prepared` (RayContext(ray)): a
// shadow ray tried against a light's recent blockers, then walked, divides once, not per test.
bool occluded(const RenderScene& rs, const Ray& ray, const RayContext& prepared, LightingMode mode, uint32_t channels, uint32_t* blocker);
bool blockedByBrush(const RenderScene& rs, const Ray& ray, const RayContext& prepared, LightingMode mode, uint32_t slot, uint32_t channels);
// occluded() given what its first walk (rs.tracer.anyHit(prepared)) returns: a caller that knows
// the only brush the ray can hit skips that walk.
bool occludedAfter(const RenderScene& rs, const Ray& ray, const std::optional<Hit>& anyHit, LightingMode mode, uint32_t channels,
                   uint32_t* blocker);

// True when the ray reaches a sky face (or leaves the level) before anything else: sunlight.
// `skyMaterial`: 1 + the only sky material that counts (a sun's `_suntexture`), 0 any sky.
bool reachesSky(const RenderScene& rs, const Ray& ray, LightingMode mode, uint32_t skyMaterial = 0);
// reachesSky for up to TraceScene::kPacketRays rays at once, their first hits in one packet walk
// (TraceScene::closestHits): bit i answers rays[i], as reachesSky(rays[i]) would.
uint64_t reachSky(const RenderScene& rs, std::span<const Ray> rays, LightingMode mode, uint32_t skyMaterial = 0);

// How far a ray from `origin` along `dir` gets before a face that blocks faithful light, or
// `depth` when it meets none (or the sky: ericw-tools' dirt counts only solid hits) within it.
float blockedDistance(const RenderScene& rs, const glm::vec3& origin, const glm::vec3& dir, float depth);

// How far a ray from `origin` along `dir` gets before a face that blocks faithful light or a sky
// face, or `depth` when it meets neither within it: where the compiler's rays stop (Embree's
// closest hit among its solid and sky faces), for the visapprox cull (vis_approx.h).
float faceDistance(const RenderScene& rs, const glm::vec3& origin, const glm::vec3& dir, float depth);

// Per TraceScene brush slot, 1 where every face of the brush blocks faithful light and none has
// alpha-tested holes: a ray that enters such a brush from outside is blocked, whichever face it
// enters by.
std::vector<uint8_t> solidBlockers(const RenderScene& rs);

// A face point's texture coordinates in units of its texture's size (repeat wraps at 1).
glm::vec2 textureUV(const RenderScene& rs, uint32_t face, const glm::vec3& p);

// Base colour at a face point: rgb as stored (sRGB-encoded, 0..1), a = coverage.
glm::vec4 baseColorAt(const RenderScene& rs, uint32_t face, const glm::vec3& p);
glm::vec3 emissiveAt(const RenderScene& rs, uint32_t face, const glm::vec3& p); // sRGB-encoded

} // namespace bt
