#include "importers/map/brush_entities.h"
#include "quake/bspfile_q2.h"
#include "quake/entity_keys.h"
#include "scene/names.h"

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <utility>

namespace bt::map {

namespace {

using quake::findKey;

// cos and sin of an angle in degrees, exact at multiples of 90: prefabs are mostly turned by
// right angles, and sin(pi) = 1.2e-16 would put integer corners a hair off the grid.
std::pair<double, double> cosSinDegrees(double degrees) {
  const double quarterTurns = degrees / 90.0;
  if (quarterTurns == std::round(quarterTurns)) {
    switch ((static_cast<int>(std::fmod(quarterTurns, 4.0)) + 4) % 4) {
    case 0: return {1.0, 0.0};
    case 1: return {0.0, 1.0};
    case 2: return {-1.0, 0.0};
    default: return {0.0, -1.0};
    }
  }
  const double radians = degrees * std::numbers::pi / 180.0;
  return {std::cos(radians), std::sin(radians)};
}

// Right-handed rotations about the world axes (qbsp's RotateAboutX/Y/Z), glm's column-major order.
glm::dmat3 rotationAboutX(double degrees) {
  const auto [c, s] = cosSinDegrees(degrees);
  return glm::dmat3(1, 0, 0, 0, c, s, 0, -s, c);
}
glm::dmat3 rotationAboutY(double degrees) {
  const auto [c, s] = cosSinDegrees(degrees);
  return glm::dmat3(c, 0, -s, 0, 1, 0, s, 0, c);
}
glm::dmat3 rotationAboutZ(double degrees) {
  const auto [c, s] = cosSinDegrees(degrees);
  return glm::dmat3(c, s, 0, -s, c, 0, 0, 0, 1);
}

} // namespace

TexVecs Placement::apply(const TexVecs& vecs) const {
  // s(p) = dot(axis, p) + offset must equal s'(p') with p' = L p + T:
  // axis' = L^-T axis, offset' = offset - dot(axis', T).
  const glm::dmat3 inverseTranspose = glm::transpose(glm::inverse(linear));
  TexVecs out;
  for (int i = 0; i < 2; ++i) {
    out.axis[i] = inverseTranspose * vecs.axis[i];
    out.offset[i] = vecs.offset[i] - glm::dot(out.axis[i], translation);
  }
  return out;
}

int readVector(std::string_view value, dvec3& out) {
  out = dvec3(0.0);
  const auto numbers = quake::parseNumbers(value);
  if (!numbers) return 0;
  const int count = int(std::min<size_t>(numbers->size(), 3));
  for (int k = 0; k < count; ++k) out[k] = (*numbers)[k];
  return count;
}

Placement externalMapPlacement(const std::vector<std::pair<std::string, std::string>>& keys, std::vector<std::string>& warnings) {
  dvec3 origin{0.0};
  if (const std::string* v = findKey(keys, "origin")) readVector(*v, origin);

  // qbsp: "_external_map_angles" (pitch yaw roll) unless it is all zero, then "_external_map_angle" as yaw.
  dvec3 angles{0.0};
  if (const std::string* v = findKey(keys, "_external_map_angles")) readVector(*v, angles);
  if (angles == dvec3(0.0))
    if (const std::string* v = findKey(keys, "_external_map_angle")) {
      dvec3 yaw;
      readVector(*v, yaw);
      angles.y = yaw.x;
    }

  // One number scales uniformly, three per axis; none (or a zero first number) means 1.
  dvec3 scale{1.0};
  if (const std::string* v = findKey(keys, "_external_map_scale")) {
    dvec3 read;
    const int count = readVector(*v, read);
    if (count == 3)
      scale = read;
    else if (count > 0 && read.x != 0.0)
      scale = dvec3(read.x);
    if (scale.x == 0.0 || scale.y == 0.0 || scale.z == 0.0) {
      warnings.push_back("_external_map_scale \"" + *v + "\" has a zero component, which would flatten the prefab; using 1");
      scale = dvec3(1.0);
    }
  }

  const glm::dmat3 rotation = rotationAboutZ(angles.y) * rotationAboutY(angles.x) * rotationAboutX(angles.z);
  Placement placement;
  placement.linear = rotation * glm::dmat3(scale.x, 0, 0, 0, scale.y, 0, 0, 0, scale.z);
  placement.translation = origin;
  return placement;
}

std::string resolveExternalMap(const std::string& includingMap, std::string_view value) {
  std::string name(value);
  for (char& c : name)
    if (c == '\\') c = '/'; // Windows editors write backslashes
  const std::filesystem::path path(name);
  if (path.is_absolute()) return path.string();
  return (std::filesystem::path(includingMap).parent_path() / path).lexically_normal().string();
}

bool isOriginBrush(const MapBrush& brush) {
  if (brush.kind == MapBrush::Kind::Verbatim || brush.faces.empty()) return false;
  const MapFace& first = brush.faces.front();
  // Quake 2 faces carry their contents; zero means "the texture's own", and the .wal of an
  // origin texture says CONTENTS_ORIGIN, so the name decides then, as in Quake 1.
  if (first.surface && first.surface->contents != 0) return (first.surface->contents & quake::q2::CONTENTS_ORIGIN) != 0;
  const std::string name = lowercase(first.texture);
  return std::string_view(name).substr(name.find_last_of('/') + 1) == "origin";
}

bool mergedIntoWorld(std::string_view classname) {
  const std::string name = lowercase(classname);
  return name == "worldspawn" || name == "func_group" || name == "func_detail" || name == "func_detail_illusionary" ||
      name == "func_detail_wall" || name == "func_detail_fence" || name == "func_illusionary_visblocker";
}

bool isHipnoticRotator(std::string_view classname) {
  return lowercase(classname).starts_with("rotate_");
}

} // namespace bt::map
