#include "scene/scene.h"

#include "scene/names.h"

#include <glm/common.hpp>

#include <algorithm>
#include <cctype>

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

std::string_view Entity::classname() const { return value("classname"); }

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
