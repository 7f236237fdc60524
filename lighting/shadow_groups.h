// Shadow rays shared by neighbouring luxels, for the CPU bake. A large level's luxels each look at
// thousands of point lights (lqdm5: about 2,500, most behind the face or blocked, the rest seen),
// and neighbouring luxels mostly get the same answer from each, so it is worked out once per
// group of them where that can be proved, and the rays are cast only where it cannot:
//   recent       per light, the last brushes that blocked a shadow ray toward it, latest first:
//                neighbouring luxels are mostly shadowed from a light by the same few brushes of
//                a wall, so a brush test or two settle most blocked rays (visibility.h
//                blockedByBrush; on lqdm5 four brushes leave a third of the walks one leaves).
//   faceLights   set by prepareLuxelFace for the sample points of one face: the grid's fixed and
//                global lists less the point lights behind every point of the face, which the
//                face's groups then sweep instead of all the level's (lqdm5: about half of its
//                2,500 lights lie behind any one face). Exactly the lights a group drops as behind
//                it, and fewer: the groups and so the luxels stay as they were. (Chunks of 64
//                luxels that also dropped lights hidden from all of them by one brush changed
//                luxels of falloff.map: groups may not cross a chunk, and other groups make other
//                proofs, which differ where a ray grazes a tie; bench/README.md, session 14.)
//   groupLights  set by prepareLuxelGroup for a group of neighbouring sample points of one face:
//                the lights of pass 0 in the order they are summed, less the point lights that
//                light none of the points (behind all of them, or hidden from all of them by one
//                solid brush), each marked kSeenByAll where no brush comes near any segment from
//                the points to it (no shadow ray needed).
//   nearLists    set with groupLights, for each of its point lights that the last ray toward it
//                reached (as kSeenByAll is tried) and that a few brushes come near (16 at most):
//                those brushes. No other brush comes near a segment from the group to the light,
//                so a shadow ray of the group that none of them intersects is one the walk finds
//                nothing on, and one that exactly one of them intersects is one whose walk meets
//                that hit first: either way occluded()'s answer and blocker without the walk
//                (lqdm5: 25.2 million walks become 10.8 million). Two hits or more take the walk,
//                whose order picks the blocker that the recent list keeps.
// A group whose ray origins are not flat (sample points moved out of a wall) takes the pyramid
// from the middle of its box's height, every test's margin widened by half that height: each
// segment lies within that distance of the pyramid's.
// By convexity: a segment from any point of the box around the ray origins to a light passes
// through the hull of the points that the box corners' segments have inside a convex brush, and
// lies inside the pyramid from the box's face to the light. The luxels are occluded()'s but for
// the tie visibility.h blockedByBrush names and rays grazing a brush within float rounding.
#pragma once

#include "lighting/render_scene.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace bt {

inline constexpr uint32_t kSeenByAll = 0x80000000u; // a groupLights entry: light index | this bit

// ericw-tools' light cull without vis data at a receiver (vis_approx.h): the bounds of the
// compiled face it lies on (polygonBounds) and the lights' boxes (by GpuLight::visBox - 1: the
// RenderScene's, or a bake's own, LuxelBakeJob::lightBoxes). A light whose box lies apart from the
// face's gives nothing, as the compiler culls it. No receiver: no cull. A group of luxels shares
// one (faithful_light.h VisCull is this type).
struct GroupCull {
  const GpuVisBox* receiver = nullptr;
  const GpuVisBox* lights = nullptr;
  bool operator==(const GroupCull&) const = default;
};

struct ShadowCache {
  static constexpr int kRecent = 4;
  ShadowCache(const RenderScene& rs, const std::vector<uint8_t>& solid);
  const std::vector<uint8_t>* solid; // visibility.h solidBlockers()
  std::vector<uint32_t> recent;      // kRecent TraceScene brush slots per light; kNoFace: none yet
  std::vector<uint8_t> lastSeen;     // per light: the last shadow ray toward it was not blocked
  std::vector<uint32_t> faceLights;  // indices into rs.lights
  bool faceReady = false;            // faceLights holds the current face's list
  // faceLights less the lights that the cull `faceCulledWith` culls: the groups of one compiled
  // face share it. No receiver: not made for this face yet.
  std::vector<uint32_t> faceCulled;
  GroupCull faceCulledWith;
  std::vector<uint32_t> groupLights; // indices into rs.lights, with kSeenByAll
  bool grouped = false;              // groupLights holds the current group's list
  // The light cull that groupLights has applied already: a luxel of the group with this cull
  // need not test its lights again. No receiver: none.
  GroupCull groupCulledWith;
  // Per light, the brushes near the pyramid from the current group to it (nearBrushes[first,
  // first + count)), valid where `group` is the current group's number.
  struct NearList {
    uint32_t group = 0;
    uint32_t first = 0;
    uint32_t count = 0;
  };
  std::vector<NearList> nearLists;
  std::vector<uint32_t> nearBrushes; // TraceScene brush slots
  uint32_t group = 1;                // raised by each prepareLuxelGroup; no list holds it yet
};

// occluded(rs, ray, Faithful, the light's shadow channels) for a shadow ray toward light `index`,
// trying the light's recent blockers first; remembers what blocked it.
bool cachedShadowed(const RenderScene& rs, ShadowCache& cache, uint32_t index, const Ray& ray);

// Prepares cache.faceLights for the sample points of one face (normal n, one-sided) whose lowest
// height along n is `nearest`, for the groups of that face that follow.
void prepareLuxelFace(const RenderScene& rs, const glm::vec3& n, float nearest, ShadowCache& cache);

// Prepares cache.groupLights for sample `points` of one face (normal n, one-sided). Leaves the
// cache ungrouped where the points do not share one light list (two grid cells). Sweeps
// cache.faceLights where faceReady (prepared for the points' face), else the grid's lists.
// Leaves out the lights that `cull` culls (faithful light gives them nothing at these points).
void prepareLuxelGroup(const RenderScene& rs, std::span<const glm::vec3> points, const glm::vec3& n, ShadowCache& cache,
                       const GroupCull& cull = {});

} // namespace bt
