#include "scene/scene.h"

#include "scene/names.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace bt {

void Bounds::grow(const dvec3& p) {
  min = glm::min(min, p);
  max = glm::max(max, p);
}

void Bounds::grow(const Bounds& b) {
  if (b.empty()) return;
  min = glm::min(min, b.min);
  max = glm::max(max, b.max);
}

double Bounds::surfaceArea() const {
  if (empty()) return 0.0;
  const dvec3 e = extent();
  return 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
}

double TextureFrame::s(const dvec3& p) const {
  const dvec3 d = p - origin;
  return d.x * tangent.x + d.y * tangent.y + d.z * tangent.z;
}

double TextureFrame::t(const dvec3& p) const {
  const dvec3 d = p - origin;
  return d.x * bitangent.x + d.y * bitangent.y + d.z * bitangent.z;
}

std::string_view Entity::classname() const {
  return value("classname");
}

const std::string* Entity::find(std::string_view key) const {
  for (const auto& [k, v] : keys)
    if (k == key) return &v;
  return nullptr;
}

std::string_view Entity::value(std::string_view key, std::string_view fallback) const {
  const std::string* v = find(key);
  return v ? std::string_view(*v) : fallback;
}

const Entity* Scene::worldspawn() const {
  for (const Entity& e : entities)
    if (e.classname() == "worldspawn") return &e;
  return nullptr;
}

uint32_t Scene::faceEntity(uint32_t face) const {
  if (face >= faces.size()) return static_cast<uint32_t>(entities.size());
  if (faces[face].brush < brushes.size()) return brushes[faces[face].brush].entity;
  // Meshes lie in face order: the last one starting at or before the face holds it.
  auto it = std::upper_bound(meshes.begin(), meshes.end(), face, [](uint32_t f, const Mesh& m) { return f < m.firstFace; });
  if (it == meshes.begin() || face >= std::prev(it)->firstFace + std::prev(it)->faceCount) return static_cast<uint32_t>(entities.size());
  return std::prev(it)->entity;
}

// The frame (origin, tangent, bitangent in the plane) with s(p), t(p) equal to the vertices' st
// at a, b and c: tangent = grad s on the plane, solved from the two edges by the Gram matrix.
static TextureFrame triangleFrame(const MeshVertex& a, const MeshVertex& b, const MeshVertex& c) {
  const dvec3 e1 = b.position - a.position, e2 = c.position - a.position;
  const double g11 = glm::dot(e1, e1), g12 = glm::dot(e1, e2), g22 = glm::dot(e2, e2);
  const double det = g11 * g22 - g12 * g12;
  auto gradient = [&](double d1, double d2) { // the in-plane vector g with dot(g, e1) = d1, dot(g, e2) = d2
    const double x = (d1 * g22 - d2 * g12) / det, y = (d2 * g11 - d1 * g12) / det;
    return e1 * x + e2 * y;
  };
  TextureFrame frame;
  frame.tangent = gradient(b.s - a.s, c.s - a.s);
  frame.bitangent = gradient(b.t - a.t, c.t - a.t);
  // origin: the point of the plane where s = t = 0, as scene.h wants it; found from a along
  // the dual basis (tangent and bitangent may be parallel for a degenerate mapping: then a
  // itself, shifted by the s and t it has, keeps s and t right along the gradients' span).
  const double m11 = glm::dot(frame.tangent, frame.tangent), m12 = glm::dot(frame.tangent, frame.bitangent),
               m22 = glm::dot(frame.bitangent, frame.bitangent);
  const double mdet = m11 * m22 - m12 * m12;
  if (std::abs(mdet) > 1e-12 * std::max(m11 * m22, 1e-300)) {
    const double x = (a.s * m22 - a.t * m12) / mdet, y = (a.t * m11 - a.s * m12) / mdet;
    frame.origin = a.position - frame.tangent * x - frame.bitangent * y;
  } else {
    frame.origin = a.position; // st constant or degenerate: s(a) is off by a.s, kept by the shift below
    if (m11 > 0.0)
      frame.origin -= frame.tangent * (a.s / m11);
    else if (m22 > 0.0)
      frame.origin -= frame.bitangent * (a.t / m22);
  }
  return frame;
}

bool Scene::addMeshTriangle(const MeshVertex& a, const MeshVertex& b, const MeshVertex& c, const Face& model) {
  for (const MeshVertex* v : {&a, &b, &c}) // a corrupt file's: nothing to trace
    if (!std::isfinite(v->position.x + v->position.y + v->position.z + v->s + v->t)) return false;
  const dvec3 n = glm::cross(b.position - a.position, c.position - a.position);
  const double length = glm::length(n);
  if (!(length > 1e-9) || !std::isfinite(length) || meshes.empty()) return false;
  Face front = model;
  front.brush = kNoBrush;
  front.plane.normal = n / length;
  front.plane.dist = glm::dot(front.plane.normal, a.position);
  front.frame = triangleFrame(a, b, c);
  front.winding = {a.position, b.position, c.position};
  Face back = front;
  back.plane = front.plane.flipped();
  back.winding = {a.position, c.position, b.position};
  Mesh& mesh = meshes.back();
  for (const MeshVertex* v : {&a, &b, &c}) mesh.bounds.grow(v->position);
  bounds.grow(mesh.bounds);
  faces.push_back(std::move(front));
  faces.push_back(std::move(back));
  mesh.faceCount += 2;
  return true;
}

std::optional<uint32_t> Scene::findMaterial(std::string_view name) const {
  for (size_t i = 0; i < materials.size(); ++i)
    if (equalsIgnoreCase(materials[i].name, name)) return static_cast<uint32_t>(i);
  return std::nullopt;
}

const char* toString(TextureSource source) {
  switch (source) {
  case TextureSource::Missing: return "missing";
  case TextureSource::Wad2: return "wad2";
  case TextureSource::Wad3: return "wad3";
  case TextureSource::Miptex: return "miptex";
  case TextureSource::Wal: return "wal";
  case TextureSource::LooseImage: return "image";
  }
  return "unknown";
}

} // namespace bt
