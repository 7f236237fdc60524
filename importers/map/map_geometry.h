// Geometry of .map brushes as qbsp (ericw-tools) builds it: planes from three points, windings by
// clipping, and the texture projection each face line describes.
#pragma once

#include "importers/map/map_document.h"
#include "scene/scene.h"
#include "scene/winding.h"

#include <glm/geometric.hpp>

#include <array>
#include <optional>
#include <vector>

namespace bt::map {

// qbsp's texinfo vectors: s = dot(p, vecs[0].xyz) + vecs[0].w, t likewise with vecs[1].
struct TexVecs {
  std::array<dvec3, 2> axis{};
  std::array<double, 2> offset{0.0, 0.0};

  double s(const dvec3& p) const { return glm::dot(p, axis[0]) + offset[0]; }
  double t(const dvec3& p) const { return glm::dot(p, axis[1]) + offset[1]; }
};

// The plane through the three points, normal = normalize(cross(p0 - p1, p2 - p1)),
// dist = dot(p1, normal), as qbsp computes it (the points run clockwise seen from outside the
// brush, so the normal points out). std::nullopt when the points are (nearly) collinear.
std::optional<Plane> planeFromPoints(const std::array<dvec3, 3>& points);

// qbsp's texinfo vectors for a face: Standard (paraxial axes rotated, divided by scale, zero
// scale meaning 1), Valve 220 (axis / scale), brush primitives (matrix over q3map2's axis base,
// in units of a `textureWidth` x `textureHeight` texture; qbsp assumes 64x64). A projection
// that is parallel to the plane or not finite is replaced by Standard defaults as qbsp does.
TexVecs textureVecs(const TextureParams& tex, const Plane& plane, int textureWidth = 64, int textureHeight = 64);
TexVecs standardVecs(const Plane& plane, const std::array<double, 2>& offset, double rotation, const std::array<double, 2>& scale);
bool isValidProjection(const TexVecs& vecs, const dvec3& normal);

// The vectors of a face line: textureVecs of its parameters, or QuArK's "etp" projection when
// the line ends in a "//TX1" or "//TX2" comment (the texture axes follow the plane points).
TexVecs faceTextureVecs(const MapFace& face, const Plane& plane, int textureWidth = 64, int textureHeight = 64);
// std::nullopt for ordinary faces; false for QuArK's TX1, true for TX2.
std::optional<bool> quarkMode(const MapFace& face);

// The frame of scene.h from qbsp's vectors: tangent = vecs[0].xyz, bitangent = vecs[1].xyz,
// origin on the plane such that s(origin) = t(origin) = 0.
TextureFrame frameFromVecs(const TexVecs& vecs, const Plane& plane);

// Windings (scene/winding.h), with the reach and epsilon qbsp clips .map brushes with.

// How far the base winding reaches: beyond any coordinate a level may use (qbsp's world
// extent is +-65536 in 2.0), so that a corner reaching it means the brush is unbounded.
inline constexpr double kWorldExtent = 262144.0;
// qbsp's ON_EPSILON for classifying points against a plane while clipping brush windings.
inline constexpr double kOnEpsilon = 0.0001;

} // namespace bt::map

namespace bt::map {

// The Standard (QuakeEd) parameters whose projection is closest to `vecs` on `plane`: exact
// when vecs has no shear and its axes are those of the plane's paraxial table entry rotated;
// otherwise the s axis is kept and t is fitted. std::nullopt when vecs is unusable.
struct StandardParams {
  std::array<double, 2> offset{0.0, 0.0};
  double rotation = 0.0;
  std::array<double, 2> scale{1.0, 1.0};
};
std::optional<StandardParams> fitStandard(const TexVecs& vecs, const Plane& plane);

// Valve 220 parameters that reproduce `vecs` exactly: unit axes, scale = 1 / |axis|.
TextureParams valveFromVecs(const TexVecs& vecs, double rotation);

// The windings of a convex brush's faces, one per plane (empty where a plane does not touch it).
std::vector<Winding> brushWindings(const std::vector<Plane>& planes);

} // namespace bt::map
