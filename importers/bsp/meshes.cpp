#include "importers/bsp/meshes.h"

#include "scene/curves.h"

#include <algorithm>

namespace bt::bsp {
namespace {

MeshVertex meshVertex(const DrawVertex& v, const dvec3& offset) {
  return {dvec3(v.position) + offset, double(v.st.x), double(v.st.y)};
}

bt::Face faceModel(const BspFile& bsp, const Surface& s, const std::function<uint32_t(int32_t)>& material) {
  const Shader& shader = bsp.shaders[size_t(s.shader)];
  bt::Face model;
  model.texture = shader.name;
  model.material = material(s.shader);
  model.surface = SurfaceAttributes{shader.contentFlags, shader.surfaceFlags, 0.0};
  return model;
}

void addCurve(const BspFile& bsp, const Surface& s, const dvec3& offset, double maxError, Scene& scene, const bt::Face& model) {
  PatchGrid control;
  control.width = s.patchSize[0];
  control.height = s.patchSize[1];
  for (int32_t i = 0; i < control.width * control.height; ++i) {
    const DrawVertex& v = bsp.drawVertices[size_t(s.firstVertex + i)];
    control.points.push_back({dvec3(v.position) + offset, glm::dvec2(v.st)});
  }
  const PatchGrid grid = tessellatePatch(control, maxError);
  auto vertex = [&](int row, int column) {
    const PatchPoint& p = grid.at(row, column);
    return MeshVertex{p.position, p.st.x, p.st.y};
  };
  for (int i = 0; i + 1 < grid.height; ++i)
    for (int j = 0; j + 1 < grid.width; ++j) {
      scene.addMeshTriangle(vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), model);
      scene.addMeshTriangle(vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1), model);
    }
}

void addSoup(const BspFile& bsp, const Surface& s, const dvec3& offset, Scene& scene, const bt::Face& model) {
  auto vertex = [&](int32_t k) {
    return meshVertex(bsp.drawVertices[size_t(s.firstVertex + bsp.drawIndices[size_t(s.firstIndex + k)])], offset);
  };
  for (int32_t k = 0; k + 2 < s.indexCount; k += 3) scene.addMeshTriangle(vertex(k), vertex(k + 1), vertex(k + 2), model);
}

} // namespace

void addQuake3Meshes(const BspFile& bsp, const Model& model, uint32_t entity, const dvec3& offset, double curveMaxError, Scene& scene,
                     const std::function<uint32_t(int32_t shader)>& material, MeshCounts& counts) {
  for (int32_t i = 0; i < model.faceCount; ++i) {
    const Surface& s = bsp.surfaces[size_t(model.firstFace + i)];
    if (s.type != SurfaceType::Patch && s.type != SurfaceType::TriangleSoup) continue;
    if (s.type == SurfaceType::Patch) {
      PatchGrid size{s.patchSize[0], s.patchSize[1], {}};
      size.points.resize(size_t(std::max(0, s.patchSize[0] * s.patchSize[1])));
      if (!patchGridProblem(size).empty()) {
        ++counts.skipped;
        continue;
      }
    }
    const bool curve = s.type == SurfaceType::Patch;
    scene.meshes.push_back(Mesh{0, entity, curve ? MeshKind::Curve : MeshKind::TriangleSoup, uint32_t(scene.faces.size()), 0, {}});
    const bt::Face faceTemplate = faceModel(bsp, s, material);
    if (curve)
      addCurve(bsp, s, offset, curveMaxError, scene, faceTemplate);
    else
      addSoup(bsp, s, offset, scene, faceTemplate);
    if (scene.meshes.back().faceCount == 0) {
      scene.meshes.pop_back();
      continue;
    }
    ++(curve ? counts.curves : counts.soups);
  }
}

} // namespace bt::bsp
