#include "importers/map/map_scene.h"
#include "scene/names.h"

#include "importers/map/map_geometry.h"
#include "importers/map/map_parser.h"
#include "importers/textures/textures.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <unordered_map>

namespace bt::map {

namespace {

// qbsp's tolerances for "the same plane": normals within NORMAL_EPSILON, distances within DIST_EPSILON.
constexpr double kNormalEpsilon = 0.000001;
constexpr double kDistEpsilon = 0.01;

// Quake 2's SURF_NODRAW. qbsp writes such faces (when they also emit light) with default
// QuakeEd texturing whatever the face line says: seen in its output for ericw-tools' test maps
// q2_nodraw_light and q2_nodraw_detail_light.
// qbsp drops NODRAW from faces that are also SKY ("fixes a bug in some old maps"), so those keep theirs.
constexpr int32_t kSurfSky = 0x4;
constexpr int32_t kSurfNoDraw = 0x80;
bool drawsNothing(const MapFace& f) {
  return f.surface && (f.surface->flags & kSurfNoDraw) != 0 && (f.surface->flags & kSurfSky) == 0;
}

bool samePlane(const Plane& a, const Plane& b) {
  return std::fabs(a.normal.x - b.normal.x) < kNormalEpsilon && std::fabs(a.normal.y - b.normal.y) < kNormalEpsilon &&
         std::fabs(a.normal.z - b.normal.z) < kNormalEpsilon && std::fabs(a.dist - b.dist) < kDistEpsilon;
}

class SceneBuilder {
public:
  SceneBuilder(const MapDocument& doc, const std::vector<Material>* loaded) : doc_(doc), loaded_(loaded) {
    scene_.sourcePath = doc.path;
    scene_.format = toString(doc.dialect);
  }

  Scene build() {
    size_t verbatim = 0;
    for (const MapEntity& me : doc_.entities) {
      Entity e;
      e.line = me.line;
      e.keys = me.keys;
      e.firstBrush = static_cast<uint32_t>(scene_.brushes.size());
      const auto entityIndex = static_cast<uint32_t>(scene_.entities.size());
      for (const MapBrush& mb : me.brushes) {
        if (mb.kind == MapBrush::Kind::Verbatim) {
          ++verbatim;
          continue;
        }
        buildBrush(mb, entityIndex);
      }
      e.brushCount = static_cast<uint32_t>(scene_.brushes.size()) - e.firstBrush;
      scene_.entities.push_back(std::move(e));
    }
    if (verbatim > 0)
      report(Severity::Note, 0, 0,
             fmt::format("{} patch or unknown block(s) kept verbatim for writing but not built into geometry", verbatim));
    return std::move(scene_);
  }

private:
  struct Side {
    const MapFace* face;
    Plane plane;
  };

  void report(Severity severity, int line, int column, std::string message) {
    scene_.diagnostics.push_back(Diagnostic{severity, doc_.path, line, column, std::move(message)});
  }

  void buildBrush(const MapBrush& mb, uint32_t entityIndex) {
    std::vector<Side> sides;
    sides.reserve(mb.faces.size());
    for (const MapFace& f : mb.faces) {
      const std::optional<Plane> plane = planeFromPoints(f.points);
      if (!plane) {
        report(Severity::Warning, f.line, f.column, "face skipped: its three points are collinear (degenerate plane)");
        continue;
      }
      bool keep = true;
      for (const Side& s : sides) {
        if (samePlane(s.plane, *plane)) {
          report(Severity::Warning, f.line, f.column, fmt::format("face skipped: same plane as the face on line {}", s.face->line));
          keep = false;
          break;
        }
        if (samePlane(s.plane, plane->flipped())) {
          report(Severity::Warning, mb.line, mb.column,
                 fmt::format("brush skipped: faces on lines {} and {} are opposite on one plane (no volume)", s.face->line, f.line));
          return;
        }
      }
      if (keep) sides.push_back({&f, *plane});
    }

    std::vector<Plane> planes;
    for (const auto& side : sides) planes.push_back(side.plane);
    std::vector<Winding> windings = brushWindings(planes);
    size_t withArea = 0;
    for (const Winding& w : windings) {
      if (w.size() < 3) continue;
      for (const dvec3& p : w) {
        // A corner out at the base square's reach: nothing clipped this side on that way.
        if (std::fabs(p.x) > kWorldExtent * 0.5 || std::fabs(p.y) > kWorldExtent * 0.5 || std::fabs(p.z) > kWorldExtent * 0.5) {
          report(Severity::Warning, mb.line, mb.column, "brush skipped: it is unbounded (its faces do not enclose a volume)");
          return;
        }
      }
      ++withArea;
    }
    if (withArea < 4) {
      report(Severity::Warning, mb.line, mb.column, "brush skipped: it has no volume");
      return;
    }

    Brush brush;
    brush.line = mb.line;
    brush.entity = entityIndex;
    brush.firstFace = static_cast<uint32_t>(scene_.faces.size());
    const auto brushIndex = static_cast<uint32_t>(scene_.brushes.size());
    for (size_t i = 0; i < sides.size(); ++i) {
      if (windings[i].size() < 3) {
        // A plane that touches the brush in an edge or not at all: qbsp drops it too.
        report(Severity::Note, sides[i].face->line, sides[i].face->column, "face dropped: its plane does not touch the brush in an area");
        continue;
      }
      const MapFace& mf = *sides[i].face;
      Face face;
      face.line = mf.line;
      face.brush = brushIndex;
      face.texture = mf.texture;
      face.material = materialFor(mf.texture);
      face.plane = sides[i].plane;
      int width = 64, height = 64;
      if (loaded_ && face.material < loaded_->size()) {
        width = (*loaded_)[face.material].width;
        height = (*loaded_)[face.material].height;
      }
      face.frame = frameFromVecs(drawsNothing(mf) ? standardVecs(face.plane, {0.0, 0.0}, 0.0, {1.0, 1.0})
                                                  : faceTextureVecs(mf, face.plane, width, height),
                                 face.plane);
      face.surface = mf.surface;
      face.winding = std::move(windings[i]);
      for (const dvec3& p : face.winding) brush.bounds.grow(p);
      scene_.faces.push_back(std::move(face));
    }
    brush.faceCount = static_cast<uint32_t>(scene_.faces.size()) - brush.firstFace;
    scene_.bounds.grow(brush.bounds);
    scene_.brushes.push_back(brush);
  }

  uint32_t materialFor(const std::string& name) {
    const auto [it, inserted] = materialIndex_.try_emplace(lowercase(name), static_cast<uint32_t>(scene_.materials.size()));
    if (inserted) {
      Material m;
      m.name = name;
      scene_.materials.push_back(std::move(m));
    }
    return it->second;
  }

  const MapDocument& doc_;
  const std::vector<Material>* loaded_;
  Scene scene_;
  std::unordered_map<std::string, uint32_t> materialIndex_;
};

} // namespace

Scene buildScene(const MapDocument& doc, const std::vector<Material>* loaded) { return SceneBuilder(doc, loaded).build(); }

Scene importMap(const std::string& path, const ImportOptions& options) {
  const MapDocument doc = readMapFile(path, options.dialect);
  Scene scene = buildScene(doc);
  loadMaterials(scene, options.textures);
  const bool brushPrimitives = std::any_of(doc.entities.begin(), doc.entities.end(), [](const MapEntity& e) {
    return std::any_of(e.brushes.begin(), e.brushes.end(), [](const MapBrush& b) { return b.kind == MapBrush::Kind::BrushDef; });
  });
  if (!brushPrimitives) return scene;
  // brushDef matrices are in texture widths: now that the sizes are known, build the frames again.
  // Materials come out in the same order, since the document is the same.
  Scene sized = buildScene(doc, &scene.materials);
  sized.materials = std::move(scene.materials);
  sized.diagnostics = std::move(scene.diagnostics);
  return sized;
}

} // namespace bt::map
