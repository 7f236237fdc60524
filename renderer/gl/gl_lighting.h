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
//   entries: the number of brushes B, then B ranges of Scene::faces (firstFace, faceCount):
//            the face's own brush, then LiquidCsg::others() in order (keptFaceAt's brushes);
//            then, per other brush in that order that can hold a point of the face's plane
//            (LiquidCsg::against), sides.size() << 2 | touching << 1 | sameKind and its sides'
//            face indices (drawn()'s test, the point's part alone).
// The parts that do not depend on the point are answered here, in the Scene's double planes as
// the CPU answers them, so the GLSL rule is short: a long rule cost the megakernel a quarter of
// its samples on lq_e4m3 (bench/README.md, session 18). Empty where the LiquidCsg is.
std::vector<uint32_t> liquidCsgTable(const Scene& scene, const LiquidCsg& csg);

} // namespace bt::gl
