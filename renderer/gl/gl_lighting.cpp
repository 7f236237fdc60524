#include "renderer/gl/gl_lighting.h"

#include <cstring>
#include <type_traits>

namespace bt::gl {

namespace {

// GlLight and GlEmitter are the CPU structs byte for byte (see gl_structs.h).
template <typename To, typename From>
std::vector<To> sameLayoutCopy(const std::vector<From>& from) {
  static_assert(sizeof(To) == sizeof(From) && std::is_trivially_copyable_v<To> && std::is_trivially_copyable_v<From>);
  std::vector<To> to(from.size());
  if (!from.empty()) std::memcpy(to.data(), from.data(), from.size() * sizeof(From));
  return to;
}

} // namespace

GlLighting lightingFor(const RenderScene& rs) {
  GlLighting out;
  out.faceFlags.reserve(rs.faces.size());
  for (const GpuShadeFace& f : rs.faces) out.faceFlags.push_back(f.flags);
  out.materialFlags.reserve(rs.materials.size());
  for (const bt::GpuMaterial& m : rs.materials)
    out.materialFlags.push_back(((m.flags & bt::kMaterialSpecular) ? kMaterialGgx : 0u) |
                                ((m.flags & bt::kMaterialEmissive) ? kMaterialHasEmissive : 0u));
  out.lights = sameLayoutCopy<GlLight>(rs.lights);
  out.surfaceLights = sameLayoutCopy<GlLight>(rs.surfaceLights);
  out.emitters = sameLayoutCopy<GlEmitter>(rs.emitters);
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
