#include "renderer/gl/gl_lighting.h"

#include "lighting/liquids.h"

namespace bt::gl {

GlLighting lightingFor(const RenderScene& rs) {
  GlLighting out;
  out.faceFlags.resize(rs.faceFlags.size());
  for (size_t f = 0; f < rs.faceFlags.size(); ++f) out.faceFlags[f] = gpuFaceWord(rs.faceFlags[f], objectChannels(rs, uint32_t(f)));
  // The CPU reference decides which materials are glossy or emissive; the GL tracer follows.
  out.materialFlags.reserve(rs.materials.size());
  for (const bt::GpuMaterial& m : rs.materials) {
    out.materialFlags.push_back(((m.flags & bt::kMaterialSpecular) ? kMaterialGgx : 0u) |
                                ((m.flags & bt::kMaterialEmissive) ? kMaterialHasEmissive : 0u) |
                                ((m.flags & bt::kMaterialBlendAdd) ? kMaterialBlendAddGl : 0u) |
                                ((m.flags & bt::kMaterialBlendFilter) ? kMaterialBlendFilterGl : 0u));
    out.materialOpacity.push_back(m.opacity);
    // Physical mode's crossing: the tint, or an additive surface's light (its tint is 1).
    const glm::vec3 crossing = (m.flags & bt::kMaterialBlendAdd) ? liquidAddedRadiance(m) : liquidTint(m);
    out.materialLiquid.push_back(glm::vec4(crossing, m.physicalOpacity));
  }
  // Lights and emitters are uploaded as the CPU reference built them (scene/gpu_structs.h).
  out.lights = rs.lights;
  out.lightGrid = rs.lightGrid;
  out.surfaceLights = rs.surfaceLights;
  out.emitters = rs.emitters;
  out.emitterArea = rs.emitterArea;
  out.minlight = rs.world.minlight;
  out.ambient = rs.world.ambient;
  out.range = rs.world.range;
  out.overbrightOne = rs.world.overbrightOne;
  out.luxelDisplay = rs.world.luxelDisplay;
  out.scaledist = rs.world.scaledist;
  out.bouncescale = rs.world.bouncescale;
  out.faithfulBounces = rs.world.bounces;
  out.litwater = rs.world.litwater;
  out.sky = rs.sky;
  out.dirt = rs.world.dirtSettings;
  out.lightKinds = rs.lightKinds;
  out.lightmaps = packLightmaps(rs.lightmaps);
  out.liquidCsg = liquidCsgTable(*rs.scene, rs.liquidCsg);
  out.blocksFromInside = rs.blocksFromInside;
  out.glassAlpha = rs.glassAlpha;
  return out;
}

std::vector<uint32_t> liquidCsgTable(const Scene& scene, const LiquidCsg& csg) {
  if (csg.empty()) return {};
  const size_t faces = scene.faces.size();
  std::vector<uint32_t> table(faces + 1);
  for (uint32_t f = 0; f < faces; ++f) {
    table[f] = uint32_t(table.size());
    if (!csg.reaches(f)) continue;
    const std::span<const LiquidCsg::Other> others = csg.others(f);
    table.push_back(uint32_t(others.size() + 1));
    const auto range = [&](uint32_t brush) {
      table.push_back(scene.brushes[brush].firstFace);
      table.push_back(scene.brushes[brush].faceCount);
    };
    range(scene.faces[f].brush);
    for (const LiquidCsg::Other& o : others) range(o.brush);
    for (const LiquidCsg::Other& o : others) {
      const LiquidCsg::Against a = LiquidCsg::against(scene, f, o.brush);
      if (a.never) continue;
      table.push_back(uint32_t(a.sides.size()) << 2 | (a.touching ? 2u : 0u) | (o.sameKind ? 1u : 0u));
      table.insert(table.end(), a.sides.begin(), a.sides.end());
    }
  }
  table[faces] = uint32_t(table.size());
  return table;
}

} // namespace bt::gl
