// The same level imported from its .map and from the .bsp qbsp compiled from it gives the same
// picture: albedo and normal AOVs rendered by the CPU backend from the same camera agree on at
// least 99 % of the pixels that can be compared.
//
// Which pixels are compared. The compiler removes faces: sides buried in other brushes or facing
// the void, and the hidden classes (skip, hint, clip, ...). The .map render skips the hidden
// classes itself (lighting/README.md), so both renders already pass through them. Sides that
// qbsp removed for lying outside the level or against another brush come back from the .bsp
// with a generated hidden name (importers/bsp/brushes.h: "skip", "*waterskip", ..., and
// "e1u1/skip" for Quake 2); where the .map shows such a side, the .bsp cannot. So a pixel is
// excluded when the .bsp render with hidden faces drawn shows a generated hidden side first
// (for instance the outer walls of a level seen from a camera outside it), and when neither
// render sees anything. Every other pixel counts: it agrees when both see a face whose albedo,
// as the 8-bit sRGB value a PNG would hold, is within kAlbedoTolerance levels per channel and
// whose normal is within kNormalToleranceDegrees.
//
// Faces the compiler removed, seen from the .map side. The .bsp importer rebuilds brushes, but
// the level qbsp drew is its faces lump, and the .map render can show a face qbsp did not keep:
// the coplanar face of the brush that `_chop_order` ranks lower (q2_chop_order_1). (Liquids
// merged by qbsp's CSG, q1_csg_water_eats_water and q2_csg_water_water_current90, the .map render
// merges itself: lighting/liquid_csg.h.) There the two pictures may rightly differ. So a pixel
// that differs is excluded when the compiled level does not decide it (CompiledFaces): no face
// with the .map face's texture is drawn on that plane at
// the point the .map render shows, or the .bsp render's face is drawn there too, on the same
// plane, with the point on the boundary between the two (a ray exactly on the edge of two
// coplanar faces may see either). A pixel that agrees always counts, so the rule can only take
// out differences, and kMaxUndecidedFraction bounds how many per level: a broken importer shows
// up as more differences than any compiler removal explains.
//
// Textures. qbsp -notex keeps only names, so the .bsp's textures are looked up exactly as the
// .map's are (its WADs and texture folders, relative to the .map): the oracle keeps the .bsp
// files in a folder of their own, not beside their sources as a mapper's would be.
#include "importers/bsp/bsp_import.h"
#include "importers/import.h"
#include "importers/textures/textures.h"
#include "scene/color.h"
#include "renderer/cpu/cpu_renderer.h"
#include "lighting/lights.h"
#include "lighting/render_scene.h"
#include "quake/entity_keys.h"
#include "tests/test_data.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cctype>
#include <fstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace bt {
namespace {

constexpr int kWidth = 160;
constexpr int kHeight = 120;
// Texels are filtered bilinearly, and qbsp stores planes and texture axes in single precision:
// a hit seen at a grazing angle lands up to a tenth of a texel away from the .map's, which
// moves the colour at a texel edge by a few levels (deprecated/offgrid_after.map: 18 pixels of
// 19200 differ by more than 8).
constexpr float kAlbedoTolerance = 8.0f; // of 255, sRGB
constexpr float kNormalToleranceDegrees = 1.0f;
constexpr double kRequiredAgreement = 0.99;
// The compiled-face rule may not take out more than this share of a level's pixels that would be
// compared without it. The most it takes on the oracle is 5.4 % (q2_chop_order_1: 136 of 2510).
constexpr double kMaxUndecidedFraction = 0.10;

bool isGeneratedHiddenSide(std::string_view texture) {
  return texture == "skip" || texture == "*waterskip" || texture == "*slimeskip" || texture == "*lavaskip" || texture == "skyskip" ||
      texture == "e1u1/skip";
}

// The .bsp's scene with its textures found where its source .map's are.
Scene importBspBesideMap(const bsp::BspFile& file, const std::filesystem::path& bspPath, const std::filesystem::path& mapPath) {
  const TextureSearch search;
  return bsp::sceneFromBsp(file, [&](Scene& scene) {
    scene.sourcePath = mapPath.string(); // where loadMaterials resolves relative WADs and folders
    loadMaterials(scene, search);
    scene.sourcePath = bspPath.string();
  });
}

// The faces qbsp drew: the polygons of the .bsp's faces lump (Q1/HL/Q2), each with the plane it
// lies on and its texture name, bucketed by plane distance so a point query looks at a handful.
// Read straight from the file (readBspFile only validates it), so no importer code decides what
// counts as compiled. Faces stay where the file has them: the brush model of an entity with an
// origin (Hexen II rotators) lies around its origin, so its faces are not found at the .map's
// position, which only matters where the pictures differ. Quake 3 draw surfaces are not read
// (the oracle has no Quake 3 level); for one, every difference would count against the bound.
class CompiledFaces {
public:
  explicit CompiledFaces(const bsp::BspFile& file)
      : nameLength_(file.version == bsp::Version::Quake2_38 ? kQuake2NameLength : kQuakeNameLength) {
    for (const bsp::Face& face : file.faces) {
      std::vector<dvec3> vertices;
      for (int32_t i = 0; i < face.edgeCount; ++i) {
        const int32_t surfedge = file.surfedges[size_t(face.firstEdge + i)];
        const auto& edge = file.edges[size_t(std::abs(surfedge))];
        vertices.push_back(dvec3(file.vertices[surfedge >= 0 ? edge[0] : edge[1]]));
      }
      Polygon polygon;
      const bsp::BspPlane& plane = file.planes[size_t(face.plane)];
      polygon.plane = {dvec3(plane.normal), double(plane.dist)};
      if (face.side) polygon.plane = polygon.plane.flipped();
      polygon.texture = lowercase(file.texinfo[size_t(face.texinfo)].texture);
      if (!polygon.setVertices(vertices)) continue;
      // Under both orientations: a face seen from behind still lies on the plane.
      const uint32_t index = uint32_t(polygons_.size());
      buckets_[distanceCell(polygon.plane.dist)].push_back(index);
      buckets_[distanceCell(-polygon.plane.dist)].push_back(index);
      polygons_.push_back(std::move(polygon));
    }
  }

  // Whether a compiled face with this texture lies on `plane` (either way round; normals within
  // kNormalEpsilon, distances within kDistanceEpsilon, qbsp's plane-merging epsilon) and covers
  // `p` (within kInsideEpsilon of its polygon).
  bool draws(const Plane& plane, const dvec3& p, std::string_view texture) const {
    const std::string name = storedName(texture);
    const int64_t last = distanceCell(plane.dist + kDistanceEpsilon);
    for (int64_t cell = distanceCell(plane.dist - kDistanceEpsilon); cell <= last; ++cell) {
      const auto bucket = buckets_.find(cell);
      if (bucket == buckets_.end()) continue;
      for (uint32_t index : bucket->second) {
        const Polygon& polygon = polygons_[index];
        if (polygon.onPlane(plane) && polygon.texture == name && polygon.contains(p)) return true;
      }
    }
    return false;
  }

  // Whether two texture names are one as the .bsp stores them.
  bool sameTexture(std::string_view a, std::string_view b) const { return storedName(a) == storedName(b); }

private:
  static constexpr double kNormalEpsilon = 1e-3;
  static constexpr double kDistanceEpsilon = 0.1;
  static constexpr double kInsideEpsilon = 0.5;
  // Texture names are stored in fixed NUL-terminated fields: 16 bytes in a Quake miptex, 32 in a
  // Quake 2 texinfo. qbsp cuts longer names there (q1_missing_texture, q2_long_texture_name).
  static constexpr size_t kQuakeNameLength = 15;
  static constexpr size_t kQuake2NameLength = 31;

  struct Polygon {
    Plane plane;
    std::string texture;
    struct Edge {
      dvec3 start;
      dvec3 inward; // unit, in the plane, pointing into the polygon
    };
    std::vector<Edge> edges;

    // False for a degenerate polygon (no area).
    bool setVertices(const std::vector<dvec3>& vertices) {
      dvec3 normal(0.0); // Newell's method: independent of which way qbsp wound the face
      for (size_t i = 0; i < vertices.size(); ++i) normal += glm::cross(vertices[i], vertices[(i + 1) % vertices.size()]);
      if (glm::length(normal) < 1e-6) return false;
      normal = glm::normalize(normal);
      for (size_t i = 0; i < vertices.size(); ++i) {
        const dvec3 along = vertices[(i + 1) % vertices.size()] - vertices[i];
        if (glm::length(along) >= 1e-6) edges.push_back({vertices[i], glm::normalize(glm::cross(normal, along))});
      }
      return true;
    }
    bool onPlane(const Plane& other) const {
      const auto near = [](const Plane& a, const Plane& b) {
        return glm::length(a.normal - b.normal) <= kNormalEpsilon && std::abs(a.dist - b.dist) <= kDistanceEpsilon;
      };
      return near(plane, other) || near(plane.flipped(), other);
    }
    bool contains(const dvec3& p) const {
      return std::all_of(edges.begin(), edges.end(), [&](const Edge& e) { return glm::dot(p - e.start, e.inward) >= -kInsideEpsilon; });
    }
  };

  std::string storedName(std::string_view texture) const { return lowercase(texture.substr(0, nameLength_)); }
  static int64_t distanceCell(double dist) { return int64_t(std::floor(dist)); }
  static std::string lowercase(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
  }

  size_t nameLength_;
  std::vector<Polygon> polygons_;
  std::unordered_map<int64_t, std::vector<uint32_t>> buckets_;
};

struct Agreement {
  size_t compared = 0, agreeing = 0, excluded = 0;
  // Of `excluded`, differing pixels the compiled level does not decide (see compareImages).
  size_t notCompiled = 0;                              // the .map shows a face the compiler removed
  size_t onCompiledEdge = 0;                           // the .bsp's face is drawn there too: the point is on their boundary
  size_t albedoOnly = 0, normalOnly = 0, coverage = 0; // kinds of disagreement
  double fraction() const { return compared ? double(agreeing) / double(compared) : 1.0; }
  // Of the pixels that would be compared without the compiled-face rule, the share it took out.
  double undecidedFraction() const {
    const size_t undecided = notCompiled + onCompiledEdge;
    return undecided ? double(undecided) / double(compared + undecided) : 0.0;
  }
};

// The point the .map render's pixel i shows, on its face's plane.
dvec3 visiblePoint(const RenderImage& image, const Camera& camera, size_t i) {
  const Ray ray = camera.ray(float(i % size_t(image.width)) + 0.5f, float(i / size_t(image.width)) + 0.5f);
  return dvec3(ray.origin) + dvec3(ray.direction) * double(image.depth[i]);
}

Agreement compareImages(const RenderImage& fromMap, const RenderImage& fromBsp, const RenderImage& bspWithHidden, const Scene& mapScene,
                        const Scene& bspScene, const CompiledFaces& compiled, const Camera& camera) {
  const float minCos = std::cos(glm::radians(kNormalToleranceDegrees));
  Agreement a;
  for (size_t i = 0; i < fromMap.face.size(); ++i) {
    const uint32_t shown = bspWithHidden.face[i];
    if ((shown && isGeneratedHiddenSide(bspScene.faces[shown - 1].texture)) || (!fromMap.face[i] && !fromBsp.face[i])) {
      ++a.excluded;
      continue;
    }
    enum class Kind { Agrees, Albedo, Normal, Coverage } kind = Kind::Coverage;
    if (fromMap.face[i] && fromBsp.face[i]) {
      const glm::vec3 d = glm::abs(linearToSrgb(fromMap.albedo[i]) - linearToSrgb(fromBsp.albedo[i])) * 255.0f;
      const bool albedo = std::max({d.x, d.y, d.z}) <= kAlbedoTolerance;
      const bool normal = glm::dot(fromMap.normal[i], fromBsp.normal[i]) >= minCos;
      kind = albedo && normal ? Kind::Agrees : normal ? Kind::Albedo : albedo ? Kind::Normal : Kind::Coverage;
    }
    if (kind != Kind::Agrees && fromMap.face[i]) {
      const Face& mapFace = mapScene.faces[fromMap.face[i] - 1];
      const dvec3 p = visiblePoint(fromMap, camera, i);
      if (!compiled.draws(mapFace.plane, p, mapFace.texture)) {
        ++a.excluded;
        ++a.notCompiled;
        continue;
      }
      const std::string_view bspTexture = fromBsp.face[i] ? bspScene.faces[fromBsp.face[i] - 1].texture : "";
      if (!bspTexture.empty() && !compiled.sameTexture(bspTexture, mapFace.texture) && compiled.draws(mapFace.plane, p, bspTexture)) {
        ++a.excluded;
        ++a.onCompiledEdge;
        continue;
      }
    }
    ++a.compared;
    switch (kind) {
    case Kind::Agrees: ++a.agreeing; break;
    case Kind::Albedo: ++a.albedoOnly; break;
    case Kind::Normal: ++a.normalOnly; break;
    case Kind::Coverage: ++a.coverage; break;
    }
  }
  return a;
}

RenderImage renderAovs(const Scene& scene, const Camera& camera, bool showHidden) {
  RenderSceneOptions options;
  options.showHidden = showHidden;
  options.bounceLights = false; // AOVs only: lq_e3m1's _bounce 3 would cost minutes of lighting
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, options, diagnostics);
  // Liquids as the level asks (_wateralpha): a translucent liquid's albedo is blended with what
  // lies behind it, so a face qbsp removed inside other liquids, or a mirrored one it kept
  // (lighting/liquid_csg.h: q1_csg_water_eats_water, q1_water_slime_zfighting), shows through.
  return renderAovsCpu(rs, camera, kWidth, kHeight);
}

// The view this comparison was tuned with, on the compiler's test maps: the default camera
// where it is an entity's own view, else the first info_player_start with Quake's 22 units of
// eye height and its yaw, else the whole map from above one corner. (The default camera turns a
// spawn's view, or picks a point of its own, on maps whose spawn sees nothing: such views look
// at faces that qbsp removes far more than these, which tells nothing about the import.)
CameraPose comparisonCamera(const Scene& scene) {
  const CameraPose pose = defaultCameraPose(scene);
  if (pose.source == "info_intermission" || pose.source == "info_player_start") return pose;
  for (const Entity& e : scene.entities)
    if (e.classname() == "info_player_start")
      if (const auto origin = quake::parseVec3(e.value("origin"))) {
        CameraPose start;
        start.origin = *origin + glm::vec3(0.0f, 0.0f, 22.0f);
        start.yaw = quake::parseFloat(e.value("angle")).value_or(0.0f);
        return start;
      }
  CameraPose whole;
  const glm::vec3 dir = glm::normalize(glm::vec3(1.0f, 1.0f, -0.8f));
  whole.origin = glm::vec3(scene.bounds.center()) - dir * 0.5f * glm::length(glm::vec3(scene.bounds.extent())) * 1.6f;
  whole.yaw = glm::degrees(std::atan2(dir.y, dir.x));
  whole.pitch = glm::degrees(std::asin(-dir.z));
  return whole;
}

// Every oracle .bsp against its .map, from the .map's camera (the .bsp has the same entities,
// so the same camera).
TEST(BspImage, MapAndBspRenderTheSameAlbedoAndNormals) {
  BT_REQUIRE_SHARED(shared);
  std::ifstream in(shared / "oracle" / "manifest.json");
  struct Result {
    std::string name;
    Agreement agreement;
  };
  std::vector<Result> results;
  for (const auto& entry : nlohmann::json::parse(in)) {
    const auto bspPath = shared / "oracle" / entry.at("bsp").get<std::string>();
    const auto mapPath = shared / entry.at("map").get<std::string>();
    SCOPED_TRACE(bspPath.string());
    const Scene fromMap = importScene(mapPath.string(), ImportOptions{});
    const bsp::BspFile file = bsp::readBspFile(bspPath);
    const Scene fromBsp = importBspBesideMap(file, bspPath, mapPath);
    const Camera camera(comparisonCamera(fromMap), kWidth, kHeight);
    const Agreement a = compareImages(renderAovs(fromMap, camera, false), renderAovs(fromBsp, camera, false),
                                      renderAovs(fromBsp, camera, true), fromMap, fromBsp, CompiledFaces(file), camera);
    EXPECT_GE(a.fraction(), kRequiredAgreement) << a.agreeing << " of " << a.compared << " pixels agree; differing albedo " << a.albedoOnly
                                                << ", normal " << a.normalOnly << ", face or none " << a.coverage;
    EXPECT_LE(a.undecidedFraction(), kMaxUndecidedFraction)
        << a.notCompiled << " differing pixels show a face the .bsp does not draw there, " << a.onCompiledEdge
        << " lie on the edge of two compiled faces: too many to be faces qbsp removed";
    results.push_back({bspPath.filename().string(), a});
  }
  EXPECT_GE(results.size(), 229u);

  std::sort(results.begin(), results.end(),
            [](const Result& x, const Result& y) { return x.agreement.fraction() < y.agreement.fraction(); });
  size_t compared = 0, agreeing = 0, nothingToCompare = 0;
  double mostUndecided = 0.0;
  for (const Result& r : results) {
    compared += r.agreement.compared;
    agreeing += r.agreement.agreeing;
    nothingToCompare += r.agreement.compared == 0;
    mostUndecided = std::max(mostUndecided, r.agreement.undecidedFraction());
  }
  // Every level, worst first: agreeing share of the compared pixels, how many were compared and
  // excluded, and what differed.
  for (const Result& r : results) {
    const Agreement& a = r.agreement;
    std::printf("  %6.2f %% of %5zu (excluded %5zu, of them not compiled %4zu + on an edge %4zu = %5.2f %%; albedo "
                "%4zu, normal %4zu, face or none %4zu)  %s\n",
                100.0 * a.fraction(), a.compared, a.excluded, a.notCompiled, a.onCompiledEdge, 100.0 * a.undecidedFraction(), a.albedoOnly,
                a.normalOnly, a.coverage, r.name.c_str());
  }
  std::printf("%zu levels, %zu pixels compared, %.3f %% agree; %zu levels show nothing comparable from their "
              "camera; the compiled-face rule took out at most %.2f %% of a level\n",
              results.size(), compared, 100.0 * double(agreeing) / double(compared), nothingToCompare, 100.0 * mostUndecided);
}

} // namespace
} // namespace bt
