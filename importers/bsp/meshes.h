// Quake 3 draw surfaces that no brush side covers: curves (MST_PATCH), tessellated as the
// engine does (scene/curves.h), and triangle soups (MST_TRIANGLE_SOUP: misc_model geometry and
// other meshes q3map2 bakes in). Planar surfaces lie on brush sides and come with the brushes;
// flares are sprites.
#pragma once

#include "importers/bsp/bsp_file.h"
#include "scene/curves.h"
#include "scene/scene.h"

#include <functional>
#include <string>

namespace bt::bsp {

struct MeshCounts {
  size_t curves = 0;
  size_t soups = 0;
  size_t skipped = 0; // patches with sizes the engine refuses
};

// Appends the model's curves and triangle soups, moved by `offset`, as meshes of `entity`. Their
// faces' frames are in texture units (drawverts' st); the caller scales them to texels.
// `material(shader)` gives the material index of a shader.
void addQuake3Meshes(const BspFile& bsp, const Model& model, uint32_t entity, const dvec3& offset, double curveMaxError, Scene& scene,
                     const std::function<uint32_t(int32_t shader)>& material, MeshCounts& counts);

} // namespace bt::bsp
