// A light tree for physical mode's light selection: a bounding volume hierarchy over the point
// lights, walked from the root to one light by the importance of each child at the shaded
// point. This is pbrt-v4's BVHLightSampler (Pharr, Jakob, Humphreys, "Physically Based
// Rendering", 4th ed., section 12.6.3; after Conty Estevez & Kulla, "Importance Sampling of Many
// Lights with Adaptive Tree Splitting", 2018), with two changes for Quake's lights:
//  - every light is omnidirectional to the tree (spot cones are left to the light itself), so a
//    node keeps no direction cone: its importance is power x cos bound / distance^2;
//  - a light ends at its reach (physical_light.h's window), so the importance is also scaled by
//    the window at the node box's nearest point, computed with the largest reach among the
//    members: a node wholly beyond every member's reach has importance 0 and is never entered.
// A pick costs two importances per level of the tree, not the level's light count.
//
// Measured against the light grid's near lists (lighting/README.md, "Light selection";
// bench/README.md, "Issue 18: many lights, session 14"), the tree is the noisier pick on the
// shared levels and the quieter one in a synthetic hall of short-reach lights, so the renderer
// picks from the near lists and the tree is the CPU's IntegratorSettings::PhysicalPick::Tree.
#pragma once

#include "scene/gpu_structs.h"

#include <glm/vec3.hpp>

#include <span>
#include <vector>

namespace bt {

// A node, in depth-first order: an inner node's first child follows it, its second is at
// `second`; a leaf holds one light. The box of the members' positions (with their _deviance
// jitter), their summed power, and the largest reach among them bound what they can light.
struct LightTreeNode {
  glm::vec3 lo{0.0f};
  float power = 0.0f; // sum over members of physical::colourSum x physicalIntensity
  glm::vec3 hi{0.0f};
  float invReach = 0.0f; // 1 / (the largest member reach, padded); 0: a member never ends
  uint32_t second = 0;   // inner: the second child; 0 for a leaf
  uint32_t light = 0;    // leaf: index into the light list
};

// The tree over lights[i] for i in `candidates` (physical mode's point lights; light_grid.h's
// physical list), each weighed by its physical intensity and emitted colour (physical_light.h). Lights
// of no power are left out. Empty when no light has power.
std::vector<LightTreeNode> buildLightTree(const std::vector<GpuLight>& lights, std::span<const uint32_t> candidates, float scaledist);

// A node's importance at point p with shading normal n: an upper estimate of its members'
// unshadowed light on the plane of n, 0 only where none of them can light p (behind the plane,
// or beyond every member's reach). Never negative or NaN.
float lightNodeImportance(const LightTreeNode& node, const glm::vec3& p, const glm::vec3& n);

struct LightPick {
  bool found = false;
  uint32_t light = 0; // index into the light list
  float pdf = 0.0f;   // the probability of this pick, the product of the branch probabilities
};

// One light by a walk from the root, each step to a child with probability proportional to
// its importance, `u` (uniform in [0, 1)) rescaled at each step (pbrt-v4's reuse of one sample).
// Not found when no light can light p (or, rarely, where a node's bound lets p see it but
// neither child's does).
LightPick pickLightFromTree(std::span<const LightTreeNode> nodes, const glm::vec3& p, const glm::vec3& n, float u);

} // namespace bt
