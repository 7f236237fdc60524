// Our texture frames against what ericw-tools qbsp compiled from the same maps (../shared/oracle):
// for every face qbsp wrote, the texel coordinates our source face gives at each of its vertices
// must equal qbsp's texinfo within 0.01 texel. Brush entity models are compared where the engine
// draws them, at their entity's "origin" (qbsp compiles origin-brush models around it).
#include "importers/bsp/bsp_file.h"
#include "importers/bsp/entities.h"
#include "importers/map/brush_entities.h"
#include "importers/map/map_parser.h"
#include "importers/map/map_scene.h"
#include "tests/test_data.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>

namespace bt::map {
namespace {

constexpr double kTexelTolerance = 0.01;

std::string lowercase(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// The name a map's texture has in the .bsp: qbsp for Quake 1 targets drops a leading path (Quake 2
// map compatibility), and the file keeps at most 15 (miptex) or 31 (Quake 2 texinfo) characters.
std::string bspTextureName(std::string_view mapName, bool quake2) {
  if (!quake2) {
    const size_t slash = mapName.rfind('/');
    if (slash != std::string_view::npos) mapName.remove_prefix(slash + 1);
  }
  return lowercase(mapName.substr(0, quake2 ? 31 : 15));
}

// How far p lies outside the convex polygon w (0 when inside or on it), measured in its plane.
double distanceOutside(const std::vector<dvec3>& w, const dvec3& normal, const dvec3& p) {
  double outside = 0.0;
  for (size_t i = 0; i < w.size(); ++i) {
    const dvec3 edge = w[(i + 1) % w.size()] - w[i];
    const dvec3 inward = glm::normalize(glm::cross(normal, edge)); // CCW seen from the front
    outside = std::max(outside, -glm::dot(p - w[i], inward));
  }
  return outside;
}

struct Candidate {
  double outside;
  double error;
};

struct MapResult {
  size_t faces = 0;     // faces qbsp wrote
  size_t matched = 0;   // of those, found among our faces and within tolerance
  size_t wrong = 0;     // found, but the texel coordinates differ
  size_t unmatched = 0; // no face of ours on that plane with that texture
  // Matched, but some vertex lies outside every one of our polygons on that plane: qbsp's face
  // polygons come out of its BSP, not from exact brush windings, and reach past ours in places.
  // Seen: brushes with near-coplanar sides (librequake dev.map line 34, three planes 0.001 apart
  // in normal: the compiled face is wider than the exact side), thin slivers along terrain edges
  // (q1_mountain.map face 929 runs 476 units past its source triangle where no source face lies),
  // Quake 2 water faces 144 units tall on a 16-unit water brush (q2_skip.map). Plane, texture and
  // texel coordinates still agree, so these pass; they are counted, with the largest distance.
  size_t uncontained = 0;
  double maxOutside = 0.0;
  std::vector<std::string> problems; // one line per face that is wrong or unmatched
};

// Where the engine draws each compiled face: its model's entity "origin" (none for the world).
std::vector<dvec3> faceOffsets(const bsp::BspFile& bsp) {
  std::vector<dvec3> offsets(bsp.faces.size(), dvec3(0.0));
  for (const Entity& e : bsp::parseEntities(bsp.entities, bsp.path)) {
    const std::string_view model = e.value("model");
    if (model.size() < 2 || model[0] != '*') continue;
    const size_t index = std::stoul(std::string(model.substr(1)));
    dvec3 origin{0.0};
    if (const std::string* v = e.find("origin")) readVector(*v, origin);
    if (index == 0 || index >= bsp.models.size()) continue;
    const bsp::Model& m = bsp.models[index];
    for (int32_t f = m.firstFace; f < m.firstFace + m.faceCount; ++f) offsets.at(static_cast<size_t>(f)) = origin;
  }
  return offsets;
}

dvec3 originOf(const Entity& e) {
  dvec3 origin{0.0};
  if (const std::string* v = e.find("origin")) readVector(*v, origin);
  return origin;
}

// The "origin" of every model's entity in the .bsp against the one our Scene gives the entity
// (from an origin brush, or 0 0 0 for a misc_external_map). qbsp numbers models in entity order:
// each entity with brushes (or a misc_external_map) whose brushes do not join the world.
//
// One exception, counted in `byNameOnly`: Quake 2 origin brushes whose face lines carry no contents.
// Their .wal says CONTENTS_ORIGIN, and we take the "origin" name for it, but id's .wal files are
// not in shared/, so the oracle's qbsp compiled them as plain brushes (their faces still match).
struct ModelOrigins {
  size_t compared = 0;
  size_t byNameOnly = 0;
};

bool originBrushKnownByNameOnly(const MapEntity& e, bool quake2) {
  return quake2 && std::any_of(e.brushes.begin(), e.brushes.end(), [](const MapBrush& b) {
           return isOriginBrush(b) && (!b.faces.front().surface || b.faces.front().surface->contents == 0);
         });
}

ModelOrigins compareModelOrigins(const MapDocument& doc, const Scene& scene, const bsp::BspFile& bsp) {
  const bool quake2 = bsp.version == bsp::Version::Quake2_38;
  ModelOrigins result;
  std::map<size_t, dvec3> compiled;
  for (const Entity& e : bsp::parseEntities(bsp.entities, bsp.path)) {
    const std::string_view model = e.value("model");
    if (model.size() >= 2 && model[0] == '*') compiled[std::stoul(std::string(model.substr(1)))] = originOf(e);
  }
  size_t model = 0;
  for (size_t i = 1; i < scene.entities.size(); ++i) {
    const Entity& e = scene.entities[i];
    const bool external = e.find("_external_map") != nullptr; // a misc_external_map, now of its new class
    if ((doc.entities[i].brushes.empty() && !external) || mergedIntoWorld(e.classname()) || e.classname() == "func_areaportal") continue;
    ++model;
    const auto it = compiled.find(model);
    if (it == compiled.end()) {
      ADD_FAILURE() << "entity on line " << e.line << " ('" << e.classname() << "') should be model *" << model
                    << ", which the .bsp does not name";
      continue;
    }
    if (originBrushKnownByNameOnly(doc.entities[i], quake2)) {
      ++result.byNameOnly;
      continue;
    }
    const dvec3 ours = originOf(e);
    EXPECT_LT(glm::length(ours - it->second), 0.01)
        << "model *" << model << " ('" << e.classname() << "', line " << e.line << "): origin " << it->second.x << " " << it->second.y
        << " " << it->second.z << " in the .bsp, " << ours.x << " " << ours.y << " " << ours.z << " in our Scene";
    ++result.compared;
  }
  return result;
}

MapResult compareWithOracle(const Scene& scene, const bsp::BspFile& bsp) {
  const std::vector<dvec3> offsets = faceOffsets(bsp);
  const bool quake2 = bsp.version == bsp::Version::Quake2_38;
  std::multimap<std::string, const Face*> byTexture;
  for (const Face& f : scene.faces) byTexture.emplace(bspTextureName(f.texture, quake2), &f);

  MapResult result;
  for (size_t i = 0; i < bsp.faces.size(); ++i) {
    const bsp::Face& bf = bsp.faces[i];
    const bsp::TexInfo& ti = bsp.texinfo[bf.texinfo];
    const auto& plane = bsp.planes[bf.plane];
    const dvec3 offset = offsets[i];
    dvec3 normal = glm::dvec3(plane.normal);
    double dist = plane.dist + glm::dot(normal, offset);
    if (bf.side) {
      normal = -normal;
      dist = -dist;
    }
    const std::vector<dvec3> verts = bsp.faceVertices(i); // model space
    ++result.faces;

    // Every vertex of a compiled face lies in some source face with that plane and texture (qbsp
    // merges neighbouring fragments only when their texinfo is the same), and there the texel
    // coordinates must agree. Per vertex: the closest frame among the source faces that contain
    // it, or among all of them when none does (then `outside` says by how much).
    std::vector<const Face*> sources;
    const auto [first, last] = byTexture.equal_range(lowercase(bsp.faceTexture(i)));
    for (auto it = first; it != last; ++it) {
      const Face& f = *it->second;
      // qbsp also writes liquid faces mirrored, facing into the liquid: same texinfo, flipped plane.
      const bool same = glm::dot(f.plane.normal, normal) > 0.9999 && std::fabs(f.plane.dist - dist) < 0.05;
      const bool mirrored = glm::dot(f.plane.normal, normal) < -0.9999 && std::fabs(f.plane.dist + dist) < 0.05;
      if (same || mirrored) sources.push_back(&f);
    }
    std::optional<Candidate> best;
    if (!sources.empty()) {
      best = Candidate{0.0, 0.0};
      for (const dvec3& local : verts) {
        const dvec3 p = local + offset;
        const double s = local.x * ti.vecs[0][0] + local.y * ti.vecs[0][1] + local.z * ti.vecs[0][2] + ti.vecs[0][3];
        const double t = local.x * ti.vecs[1][0] + local.y * ti.vecs[1][1] + local.z * ti.vecs[1][2] + ti.vecs[1][3];
        std::optional<Candidate> atVertex;
        for (const Face* f : sources) {
          const Candidate c{distanceOutside(f->winding, f->plane.normal, p),
                            std::max(std::fabs(f->frame.s(p) - s), std::fabs(f->frame.t(p) - t))};
          const bool contains = c.outside < 0.1;
          const bool bestContains = atVertex && atVertex->outside < 0.1;
          if (!atVertex || (contains && !bestContains) ||
              (contains == bestContains && (contains ? c.error < atVertex->error : c.outside < atVertex->outside)))
            atVertex = c;
        }
        best->outside = std::max(best->outside, atVertex->outside);
        best->error = std::max(best->error, atVertex->error);
      }
    }
    if (!best) {
      ++result.unmatched;
      result.problems.push_back(
          fmt::format("face {} '{}': no source face on plane ({} {} {}) {}", i, bsp.faceTexture(i), normal.x, normal.y, normal.z, dist));
    } else if (best->error > kTexelTolerance) {
      ++result.wrong;
      result.problems.push_back(fmt::format("face {} '{}': texel coordinates off by {} (vertex outside source by {})", i,
                                            bsp.faceTexture(i), best->error, best->outside));
    } else {
      ++result.matched;
      result.maxOutside = std::max(result.maxOutside, best->outside);
      result.uncontained += best->outside >= 0.1;
    }
  }
  return result;
}

TEST(QbspOracle, EveryCompiledFaceHasOurTexelCoordinates) {
  BT_REQUIRE_SHARED(shared);
  std::ifstream manifestFile(shared / "oracle" / "manifest.json");
  ASSERT_TRUE(manifestFile) << "oracle/manifest.json missing";
  const auto manifest = nlohmann::json::parse(manifestFile);
  ASSERT_EQ(manifest.size(), 229u);

  std::map<std::string, MapResult> byDialect;
  size_t mapsPassed = 0, allFaces = 0, allGood = 0, allModels = 0, modelsByNameOnly = 0;
  std::string deviations;
  for (const auto& entry : manifest) {
    const std::string mapPath = (shared / entry.at("map").get<std::string>()).string();
    const std::string bspPath = (shared / "oracle" / entry.at("bsp").get<std::string>()).string();
    SCOPED_TRACE(mapPath);
    const MapDocument doc = readMapFile(mapPath);
    const Scene scene = buildScene(doc);
    const bsp::BspFile bsp = bsp::readBspFile(std::filesystem::path(bspPath));
    const MapResult r = compareWithOracle(scene, bsp);
    const ModelOrigins models = compareModelOrigins(doc, scene, bsp);
    allModels += models.compared;
    modelsByNameOnly += models.byNameOnly;
    MapResult& total = byDialect[toString(doc.dialect)];
    total.faces += r.faces;
    total.matched += r.matched;
    total.wrong += r.wrong;
    total.unmatched += r.unmatched;
    total.uncontained += r.uncontained;
    total.maxOutside = std::max(total.maxOutside, r.maxOutside);
    // Every compiled face is paired with a source face and agrees with it; any that is not is
    // listed (all of them, so that a regression shows what moved).
    EXPECT_EQ(r.wrong + r.unmatched, 0u) << r.wrong + r.unmatched << " of " << r.faces << " faces differ; first: " << r.problems.front();
    if (!r.problems.empty()) {
      deviations += fmt::format("  {}: {} of {} faces off\n", entry.at("map").get<std::string>(), r.problems.size(), r.faces);
      for (const std::string& problem : r.problems) deviations += "    " + problem + "\n";
    }
    mapsPassed += r.wrong == 0 && r.unmatched == 0;
    allFaces += r.faces;
    allGood += r.matched;
  }
  EXPECT_EQ(mapsPassed, manifest.size());
  EXPECT_EQ(allGood, allFaces);
  std::string summary = fmt::format("{} of {} maps match qbsp face by face; {} brush models' origins agree ({} Quake 2 origin brushes "
                                    "known by texture name only, which the oracle's qbsp had no .wal for)\n",
                                    mapsPassed, manifest.size(), allModels, modelsByNameOnly);
  for (const auto& [dialect, r] : byDialect)
    summary +=
        fmt::format("  {:<14} faces {:>6}  matched {:>6}  wrong {:>4}  unmatched {:>4}  polygon past ours {:>3} (by up to {:.3g} units)\n",
                    dialect, r.faces, r.matched, r.wrong, r.unmatched, r.uncontained, r.maxOutside);
  std::cout << summary << (deviations.empty() ? "every compiled face paired and within tolerance\n" : "faces that differ:\n" + deviations);
  RecordProperty("summary", summary);
}

} // namespace
} // namespace bt::map
