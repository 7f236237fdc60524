// What qbsp (ericw-tools) does to brush entities before it compiles them, where it changes what
// the game shows: misc_external_map prefabs and origin brushes.
//
// - misc_external_map: qbsp reads the brushes of another .map ("_external_map"), scales them
//   ("_external_map_scale"), rotates them ("_external_map_angles" pitch yaw roll, or the yaw
//   "_external_map_angle"), moves them to the entity's "origin", and makes the entity a
//   "_external_map_classname" (func_group, func_wall, ...) with "origin" "0 0 0". Textures stay
//   locked to the moved faces. External maps do not nest: qbsp takes every brush of the file and
//   ignores its point entities, misc_external_map included.
// - Origin brushes (texture "origin", or Quake 2's CONTENTS_ORIGIN): qbsp sets the entity's
//   "origin" to the centre of the brush's bounds and compiles the model around it (brushes moved
//   by -origin, texture offsets shifted so the texture stays put). The engine draws the model at
//   its origin, so in game it sits where the source has it. Hipnotic's rotate_* entities without
//   an origin brush take the origin of their "target" the same way.
#pragma once

#include "importers/map/map_document.h"
#include "importers/map/map_geometry.h"

#include <glm/mat3x3.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace bt::map {

// An affine move of source brushes into the level, p' = linear * p + translation.
struct Placement {
  glm::dmat3 linear{1.0};
  dvec3 translation{0.0};

  dvec3 apply(const dvec3& p) const { return linear * p + translation; }
  // The texture vectors that give a moved point the texel coordinates the source point had
  // (qbsp's texture lock): axes through the inverse transpose, offsets shifted by the move.
  TexVecs apply(const TexVecs& vecs) const;
};

// The key's value as a vector of up to three numbers: how many were read, as qbsp's get_vector
// (a value that breaks quake/entity_keys.h's number rule reads none).
int readVector(std::string_view value, dvec3& out);

// Where qbsp puts a misc_external_map's brushes: scale, then rotate (Z yaw * Y pitch * X roll,
// right-handed), then move to "origin". `warnings` receives what was unusable (a zero scale).
Placement externalMapPlacement(const std::vector<std::pair<std::string, std::string>>& keys, std::vector<std::string>& warnings);

// The file that "_external_map" names: relative paths are taken from the including map's folder.
std::string resolveExternalMap(const std::string& includingMap, std::string_view value);

// Brushes that mark a model's origin rather than being drawn: the first face decides, as qbsp's
// brush contents come from the first face that has any (every Quake texture has some).
bool isOriginBrush(const MapBrush& brush);

// Entities whose brushes qbsp merges into the world (worldspawn itself, func_group, the
// func_detail family): they have no model, so no origin of their own.
bool mergedIntoWorld(std::string_view classname);

// Hipnotic's rotating entities (rotate_object, rotate_door, ...): their model turns around the
// origin of the entity they target.
bool isHipnoticRotator(std::string_view classname);

} // namespace bt::map
