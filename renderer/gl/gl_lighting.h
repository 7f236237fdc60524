// The lighting the GL tracer takes, from the CPU reference's RenderScene: both tracers light
// from one classification of faces and one light list, so they cannot drift apart.
#pragma once

#include "lighting/render_scene.h"
#include "renderer/gl/gl_tracer.h"

namespace bt::gl {

GlLighting lightingFor(const RenderScene& scene);

// The rule on overlapping liquids (lighting/liquid_csg.h) as shaders/visible.glsl reads it, in
// the face-flag buffer after the level's F face flags; offsets count from there (uints):
//   [0, F]:  per face f, where its entries begin; face f's are [table[f], table[f + 1]), empty
//            where no other liquid brush reaches its brush (LiquidCsg::reaches);
//   entries: two uints per brush, its Scene::brushes range and kind: firstFace, then
//            faceCount << 1 | sameKind. A face's first entry is its own brush (sameKind 0),
//            then LiquidCsg::others() in order.
// Empty where the LiquidCsg is.
std::vector<uint32_t> liquidCsgTable(const Scene& scene, const LiquidCsg& csg);

} // namespace bt::gl
