#include "renderer/gl/gl_lighting.h"

#include <bit>

namespace bt::gl {

GlLighting lightingFor(const RenderScene& rs) {
  GlLighting out;
  out.faceFlags = rs.faceFlags;
  // The CPU reference decides which materials are glossy or emissive; the GL tracer follows.
  out.materialFlags.reserve(rs.materials.size());
  for (const bt::GpuMaterial& m : rs.materials)
    out.materialFlags.push_back(((m.flags & bt::kMaterialSpecular) ? kMaterialGgx : 0u) |
                                ((m.flags & bt::kMaterialEmissive) ? kMaterialHasEmissive : 0u));
  // GlLight and GlEmitter are the CPU structs byte for byte (gl_structs.h asserts the layout).
  for (const GpuLight& light : rs.lights) out.lights.push_back(std::bit_cast<GlLight>(light));
  for (const GpuLight& light : rs.surfaceLights) out.surfaceLights.push_back(std::bit_cast<GlLight>(light));
  for (const GpuEmitter& e : rs.emitters) out.emitters.push_back(std::bit_cast<GlEmitter>(e));
  out.emitterArea = rs.emitterArea;
  out.minlight = rs.world.minlight;
  out.range = rs.world.range;
  out.scaledist = rs.world.scaledist;
  out.bouncescale = rs.world.bouncescale;
  out.faithfulBounces = rs.world.bounces;
  out.litwater = rs.world.litwater;
  return out;
}

} // namespace bt::gl
