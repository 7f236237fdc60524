#include "importers/map/map_geometry.h"

#include "quake/texture_axes.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>

namespace bt::map {

std::optional<Plane> planeFromPoints(const std::array<dvec3, 3>& points) {
  const dvec3 n = glm::cross(points[0] - points[1], points[2] - points[1]);
  const double length = glm::length(n);
  // qbsp rejects a plane whose normal cannot be normalised; the same threshold in area terms
  // keeps tiny but valid faces (1/8-unit detail) and drops collinear points.
  if (!(length > 1e-9) || !std::isfinite(length)) return std::nullopt;
  Plane plane;
  plane.normal = n / length;
  plane.dist = glm::dot(points[1], plane.normal);
  return plane;
}

TexVecs standardVecs(const Plane& plane, const std::array<double, 2>& offset, double rotation, const std::array<double, 2>& scale) {
  const quake::TextureAxes base = quake::textureAxisFromPlane(plane.normal);
  std::array<dvec3, 2> v{base.s, base.t};

  // QuakeEd rotates within the plane of the two axes that the table's s and t vectors use.
  const double angle = rotation / 180.0 * std::numbers::pi;
  const double sinv = std::sin(angle);
  const double cosv = std::cos(angle);
  const int sv = v[0].x != 0.0 ? 0 : v[0].y != 0.0 ? 1 : 2;
  const int tv = v[1].x != 0.0 ? 0 : v[1].y != 0.0 ? 1 : 2;
  for (dvec3& a : v) {
    const double ns = cosv * a[sv] - sinv * a[tv];
    const double nt = sinv * a[sv] + cosv * a[tv];
    a[sv] = ns;
    a[tv] = nt;
  }
  TexVecs out;
  for (int i = 0; i < 2; ++i) {
    const double s = scale[i] != 0.0 ? scale[i] : 1.0; // a zero scale means "unscaled" to qbsp
    out.axis[i] = v[i] / s;
    out.offset[i] = offset[i];
  }
  return out;
}

namespace {

TexVecs valveVecs(const TextureParams& tex) {
  TexVecs out;
  for (int i = 0; i < 2; ++i) {
    out.axis[i] = tex.axis[i] / tex.scale[i];
    out.offset[i] = tex.offset[i];
  }
  return out;
}

// q3map2's ComputeAxisBase: the texture-space axes that brush primitive matrices act on.
std::array<dvec3, 2> brushPrimitiveAxisBase(dvec3 normal) {
  for (int i = 0; i < 3; ++i)
    if (std::fabs(normal[i]) < 1e-6) normal[i] = 0.0;
  const double rotY = -std::atan2(normal.z, std::sqrt(normal.y * normal.y + normal.x * normal.x));
  const double rotZ = std::atan2(normal.y, normal.x);
  return {dvec3{-std::sin(rotZ), std::cos(rotZ), 0.0},
          dvec3{-std::sin(rotY) * std::cos(rotZ), -std::sin(rotY) * std::sin(rotZ), -std::cos(rotY)}};
}

TexVecs brushPrimitiveVecs(const TextureParams& tex, const Plane& plane, int width, int height) {
  const auto [texX, texY] = brushPrimitiveAxisBase(plane.normal);
  const std::array<double, 2> size{static_cast<double>(width), static_cast<double>(height)};
  TexVecs out;
  for (int i = 0; i < 2; ++i) {
    out.axis[i] = size[i] * (texX * tex.matrix[i][0] + texY * tex.matrix[i][1]);
    out.offset[i] = size[i] * tex.matrix[i][2];
  }
  return out;
}

// qbsp's ZERO_EPSILON.
constexpr double kZeroEpsilon = 0.0001;

double roundNearInteger(double v) {
  const double r = std::rint(v);
  return std::fabs(v - r) < kZeroEpsilon ? r : v;
}

} // namespace

bool isValidProjection(const TexVecs& vecs, const dvec3& normal) {
  // qbsp's test: the texture plane's normal must not lie in the face plane.
  const dvec3 c = glm::cross(vecs.axis[0], vecs.axis[1]);
  const double len = glm::length(c);
  if (!std::isfinite(len) || len == 0.0 || !std::isfinite(vecs.offset[0]) || !std::isfinite(vecs.offset[1])) return false;
  const double cosAngle = glm::dot(c / len, normal);
  return std::isfinite(cosAngle) && std::fabs(cosAngle) >= kZeroEpsilon;
}

namespace {

// QuArK's "etp" modes (a "//TX1" or "//TX2" comment after a Standard face line): the texture
// axes are the plane points' edges, p2 - p0 and p1 - p0 (swapped for TX2), each 128 texels
// long, and p0 sits at texel (0, 0). The vectors are the dual basis of those edges in the plane.
TexVecs quarkVecs(const std::array<dvec3, 3>& points, bool tx2) {
  std::array<dvec3, 2> edge{(points[2] - points[0]) / 128.0, (points[1] - points[0]) / 128.0};
  if (tx2) std::swap(edge[0], edge[1]);
  const double a = glm::dot(edge[0], edge[0]);
  const double b = glm::dot(edge[0], edge[1]);
  const double d = glm::dot(edge[1], edge[1]);
  const double det = a * d - b * b;
  TexVecs v;
  if (std::fabs(det) >= kZeroEpsilon) {
    v.axis[0] = (d * edge[0] - b * edge[1]) / det;
    v.axis[1] = -(a * edge[1] - b * edge[0]) / det;
  } // else: zero vectors, which the validity check below replaces with defaults, as qbsp ends up doing
  for (int i = 0; i < 2; ++i) v.offset[i] = -glm::dot(v.axis[i], points[0]);
  return v;
}

// What qbsp does to every face's vectors after computing them.
TexVecs finishVecs(TexVecs v, const Plane& plane) {
  // qbsp rounds every vector component within ZERO_EPSILON of an integer (a DarkPlaces lightmap
  // size workaround), so 1/0.8574787-style scales written by editors land on round numbers.
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 3; ++j) v.axis[i][j] = roundNearInteger(v.axis[i][j]);
    v.offset[i] = roundNearInteger(v.offset[i]);
  }
  // qbsp repairs an unusable projection with default Standard texturing rather than failing.
  if (!isValidProjection(v, plane.normal)) v = standardVecs(plane, {0.0, 0.0}, 0.0, {1.0, 1.0});
  return v;
}

} // namespace

TexVecs textureVecs(const TextureParams& tex, const Plane& plane, int textureWidth, int textureHeight) {
  TexVecs v;
  switch (tex.kind) {
  case TextureKind::Standard: v = standardVecs(plane, tex.offset, tex.rotation, tex.scale); break;
  case TextureKind::Valve220: v = valveVecs(tex); break;
  case TextureKind::BrushPrimitive: v = brushPrimitiveVecs(tex, plane, textureWidth, textureHeight); break;
  }
  return finishVecs(v, plane);
}

std::optional<bool> quarkMode(const MapFace& face) {
  if (face.tex.kind != TextureKind::Standard) return std::nullopt;
  const std::string_view c = face.trailingComment;
  if (c.size() >= 5 && c.substr(0, 4) == "//TX" && (c[4] == '1' || c[4] == '2')) return c[4] == '2';
  return std::nullopt;
}

TexVecs faceTextureVecs(const MapFace& face, const Plane& plane, int textureWidth, int textureHeight) {
  if (const auto tx2 = quarkMode(face)) return finishVecs(quarkVecs(face.points, *tx2), plane);
  return textureVecs(face.tex, plane, textureWidth, textureHeight);
}

TextureFrame frameFromVecs(const TexVecs& vecs, const Plane& plane) {
  // Solve [tangent; bitangent; normal] * origin = (-offset0, -offset1, dist) by Cramer's rule.
  const dvec3& r0 = vecs.axis[0];
  const dvec3& r1 = vecs.axis[1];
  const dvec3& r2 = plane.normal;
  const dvec3 c12 = glm::cross(r1, r2);
  const double det = glm::dot(r0, c12);
  TextureFrame frame;
  frame.tangent = r0;
  frame.bitangent = r1;
  frame.origin = (-vecs.offset[0] * c12 - vecs.offset[1] * glm::cross(r2, r0) + plane.dist * glm::cross(r0, r1)) / det;
  return frame;
}

} // namespace bt::map

namespace bt::map {

namespace {
// Values within a hair of a round number are written round: a converted map stays readable.
double tidy(double v, double step) {
  const double r = std::round(v / step) * step;
  return std::fabs(r - v) < 1e-9 * std::max(1.0, std::fabs(v)) ? r : v;
}
} // namespace

std::optional<StandardParams> fitStandard(const TexVecs& vecs, const Plane& plane) {
  const quake::TextureAxes base = quake::textureAxisFromPlane(plane.normal);
  const int sv = base.s.x != 0.0 ? 0 : base.s.y != 0.0 ? 1 : 2;
  const int tv = base.t.x != 0.0 ? 0 : base.t.y != 0.0 ? 1 : 2;
  const int c = 3 - sv - tv; // the axis the table projects along
  const double a = base.s[sv];
  const double b = base.t[tv];
  const dvec3& n = plane.normal;
  if (n[c] == 0.0) return std::nullopt;

  // On the plane p[c] is a function of p[sv], p[tv]: write s and t as A*p[sv] + B*p[tv] + C.
  double A[2], B[2], C[2];
  for (int i = 0; i < 2; ++i) {
    const dvec3& v = vecs.axis[i];
    A[i] = v[sv] - v[c] * n[sv] / n[c];
    B[i] = v[tv] - v[c] * n[tv] / n[c];
    C[i] = vecs.offset[i] + v[c] * plane.dist / n[c];
  }
  // QuakeEd's s row is (cos, sin) * a / scale0 and its t row (-sin, cos) * b / scale1.
  const double r0 = std::hypot(A[0], B[0]);
  if (!(r0 > 0.0) || !std::isfinite(r0)) return std::nullopt;
  const double theta = std::atan2(a * B[0], a * A[0]);
  const double k = -A[1] * std::sin(theta) + B[1] * std::cos(theta);
  if (k == 0.0 || !std::isfinite(k)) return std::nullopt;
  StandardParams out;
  out.rotation = tidy(theta * 180.0 / std::numbers::pi, 1.0);
  out.scale = {tidy(1.0 / r0, 1.0 / 1024.0), tidy(b / k, 1.0 / 1024.0)};
  out.offset = {tidy(C[0], 1.0 / 1024.0), tidy(C[1], 1.0 / 1024.0)};
  return out;
}

TextureParams valveFromVecs(const TexVecs& vecs, double rotation) {
  TextureParams p;
  p.kind = TextureKind::Valve220;
  p.rotation = rotation;
  for (int i = 0; i < 2; ++i) {
    const double len = glm::length(vecs.axis[i]);
    p.axis[i] = len > 0.0 ? vecs.axis[i] / len : vecs.axis[i];
    p.scale[i] = len > 0.0 ? 1.0 / len : 1.0;
    p.offset[i] = vecs.offset[i];
  }
  return p;
}

std::vector<Winding> brushWindings(const std::vector<Plane>& planes) {
  std::vector<Winding> out(planes.size());
  for (size_t i = 0; i < planes.size(); ++i) {
    Winding w = baseWinding(planes[i], kWorldExtent);
    for (size_t j = 0; j < planes.size() && !w.empty(); ++j)
      if (j != i) w = clipBehind(w, planes[j], kOnEpsilon);
    out[i] = std::move(w);
  }
  return out;
}

} // namespace bt::map
