#include "viewer/picking.h"

#include "lighting/visibility.h"
#include "scene/gpu_structs.h"

#include <fmt/format.h>

namespace bt {

namespace {

std::string at(const std::string& file, int line) {
  return line > 0 ? fmt::format("{}:{}", file, line) : file + " (no line: a compiled level)";
}

// What qbsp and the tracers make of the face: Quake 2/3 contents where the format has them.
std::string kindOf(const RenderScene& rs, const Face& face, uint32_t index) {
  const uint32_t flags = rs.faceFlags[index];
  std::string kind = (flags & kFaceSky) ? "sky" : (flags & kFaceLiquid) ? "liquid" : "solid";
  if (flags & kFaceNoShadow) kind += ", casts no shadow";
  if (flags & kFaceEmissive) kind += ", emissive";
  if (face.surface)
    kind += fmt::format(" | contents 0x{:x}, surface flags 0x{:x}, value {:g}", uint32_t(face.surface->contents),
                        uint32_t(face.surface->flags), face.surface->value);
  return kind;
}

} // namespace

PickedFace pickFace(const RenderScene& rs, const CameraPose& pose, int width, int height, float x, float y) {
  PickedFace picked;
  const SurfaceHit hit = traceVisible(rs, Camera(pose, width, height).ray(x, y));
  if (!hit.found) return picked;
  const Scene& scene = *rs.scene;
  const Face& face = scene.faces[hit.face];
  const std::string& file = scene.sourcePath;
  picked.hit = true;
  picked.fileLine = face.line > 0 ? fmt::format("{}:{}", file, face.line) : "";
  picked.lines.push_back(fmt::format("face {}: {}", hit.face, at(file, face.line)));
  if (face.brush != kNoBrush)
    picked.lines.push_back(fmt::format("brush {}: {}", face.brush, at(file, scene.brushes[face.brush].line)));
  else
    picked.lines.push_back("a curve or triangle-soup triangle");
  const Material& material = scene.materials[face.material];
  picked.lines.push_back(fmt::format("texture {} ({}x{}, {})", face.texture, material.width, material.height, toString(material.source)));
  const uint32_t entity = scene.faceEntity(hit.face);
  if (entity < scene.entities.size())
    picked.lines.push_back(
        fmt::format("entity {} {}: {}", entity, scene.entities[entity].classname(), at(file, scene.entities[entity].line)));
  picked.lines.push_back(kindOf(rs, face, hit.face));
  picked.lines.push_back(fmt::format("point ({:g} {:g} {:g}), normal ({:g} {:g} {:g})", hit.position.x, hit.position.y, hit.position.z,
                                     hit.normal.x, hit.normal.y, hit.normal.z));
  return picked;
}

} // namespace bt
