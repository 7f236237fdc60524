#include "importers/map/map_scene.h"
#include "scene/names.h"

#include "importers/map/brush_entities.h"
#include "importers/map/map_geometry.h"
#include "importers/map/map_parser.h"
#include "importers/map/map_patches.h"
#include "importers/bsp/q3_shader_light.h"
#include "importers/game/game_install.h"
#include "importers/textures/textures.h"
#include "quake/bspfile_q2.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
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
bool drawsNothing(const MapFace& f) {
  return f.surface && (f.surface->flags & quake::q2::SURF_NODRAW) != 0 && (f.surface->flags & quake::q2::SURF_SKY) == 0;
}

bool samePlane(const Plane& a, const Plane& b) {
  return std::fabs(a.normal.x - b.normal.x) < kNormalEpsilon && std::fabs(a.normal.y - b.normal.y) < kNormalEpsilon &&
      std::fabs(a.normal.z - b.normal.z) < kNormalEpsilon && std::fabs(a.dist - b.dist) < kDistEpsilon;
}

// Sets the first `key` (Quake compares keys without case) to value, or adds it.
void setKey(std::vector<std::pair<std::string, std::string>>& keys, std::string_view key, std::string value) {
  for (auto& [k, v] : keys)
    if (equalsIgnoreCase(k, key)) {
      k = key; // Entity::find spells keys as the engines do
      v = std::move(value);
      return;
    }
  keys.emplace_back(std::string(key), std::move(value));
}

std::string formatVector(const dvec3& v) {
  return fmt::format("{} {} {}", v.x, v.y, v.z);
}

class SceneBuilder {
public:
  SceneBuilder(const MapDocument& doc, const std::vector<Material>* loaded, double curveMaxError)
      : doc_(doc), loaded_(loaded), curveMaxError_(curveMaxError) {
    scene_.sourcePath = doc.path;
    scene_.addInputFile(doc.path);
    scene_.format = toString(doc.dialect);
  }

  Scene build() {
    // The Scene shows the level as the game does: brush entities where the engine draws them,
    // with the keys qbsp writes for them (brush_entities.h).
    std::vector<bool> hasOriginBrush;
    for (const MapEntity& me : doc_.entities) {
      Entity e;
      e.line = me.line;
      e.keys = me.keys;
      e.firstBrush = static_cast<uint32_t>(scene_.brushes.size());
      const auto entityIndex = static_cast<uint32_t>(scene_.entities.size());
      const std::optional<dvec3> originBrush = equalsIgnoreCase(e.classname(), "misc_external_map")
          ? includeExternalMap(me, e, entityIndex)
          : buildBrushes(me.brushes, entityIndex, doc_.path, nullptr);
      e.brushCount = static_cast<uint32_t>(scene_.brushes.size()) - e.firstBrush;
      if (originBrush && mergedIntoWorld(e.classname())) {
        report(Severity::Note, doc_.path, me.line, me.column,
               fmt::format("origin brush of '{}' ignored: its brushes join the world, which has no origin (as in qbsp)", e.classname()));
      } else if (originBrush) {
        // qbsp compiles the model around this point and the engine draws it there: the brushes
        // stay where the source has them, the entity gets the origin qbsp writes.
        setKey(e.keys, "origin", formatVector(*originBrush));
      }
      hasOriginBrush.push_back(originBrush.has_value());
      scene_.entities.push_back(std::move(e));
    }
    // Hipnotic rotators turn around their target: a second pass, since it may come later in the file.
    for (size_t i = 0; i < scene_.entities.size(); ++i) {
      Entity& e = scene_.entities[i];
      if (hasOriginBrush[i] || e.brushCount == 0 || !isHipnoticRotator(e.classname())) continue;
      setKey(e.keys, "origin", formatVector(rotatorOrigin(e)));
    }
    if (verbatim_ > 0)
      report(Severity::Note, doc_.path, 0, 0,
             fmt::format("{} unknown block(s) (brushDef3 or newer) kept verbatim for writing but not built into geometry", verbatim_));
    return std::move(scene_);
  }

private:
  struct Side {
    const MapFace* face;
    Plane plane;   // where the face lies in the level
    Plane written; // the plane of its points as written: its texture projection is made there
  };

  void report(Severity severity, const std::string& file, int line, int column, std::string message) {
    scene_.diagnostics.push_back(Diagnostic{severity, file, line, column, std::move(message)});
  }

  // Builds brushes (of `file`, moved by `placement` when given) into the entity. Returns the
  // centre of the last origin brush among them: qbsp's model origin (the last one wins there too).
  std::optional<dvec3> buildBrushes(const std::vector<MapBrush>& brushes, uint32_t entityIndex, const std::string& file,
                                    const Placement* placement) {
    std::optional<dvec3> originBrush;
    for (const MapBrush& mb : brushes) {
      if (mb.kind == MapBrush::Kind::Verbatim) {
        if (isPatchBlock(mb.verbatim))
          buildPatch(mb, entityIndex, file, placement);
        else
          ++verbatim_;
        continue;
      }
      const std::optional<uint32_t> built = buildBrush(mb, entityIndex, file, placement);
      if (built && isOriginBrush(mb)) originBrush = scene_.brushes[*built].bounds.center();
    }
    return originBrush;
  }

  // misc_external_map: the brushes of every entity of the named file, placed by the entity's
  // keys, and the keys qbsp gives the entity. Unreadable or malformed prefabs stop the import,
  // as they stop qbsp.
  std::optional<dvec3> includeExternalMap(const MapEntity& me, Entity& e, uint32_t entityIndex) {
    const std::string* name = e.find("_external_map");
    if (!name || name->empty())
      throw ImportError(Diagnostic{Severity::Error, doc_.path, me.line, me.column,
                                   "misc_external_map without an \"_external_map\" key naming the .map to include"});
    const std::string path = resolveExternalMap(doc_.path, *name);
    // The name comes from the file: one the system cannot even look up (too long, ...) is not
    // found either, with the system's reason.
    std::error_code lookup;
    if (!std::filesystem::is_regular_file(path, lookup))
      throw ImportError(Diagnostic{Severity::Error, doc_.path, me.line, me.column,
                                   fmt::format("misc_external_map: \"_external_map\" \"{}\" not found (looked for {}{})", *name, path,
                                               lookup ? ": " + lookup.message() : "")});
    MapDocument external;
    scene_.addInputFile(path);
    try {
      external = readMapFile(path);
    } catch (const ImportError& error) {
      Diagnostic d = error.diagnostic();
      d.message += fmt::format(" (in the external map of the misc_external_map at {}:{})", doc_.path, me.line);
      throw ImportError(d);
    }
    if (!me.brushes.empty())
      report(Severity::Warning, doc_.path, me.line, me.column,
             fmt::format("misc_external_map has {} brush(es) of its own; ignored, as qbsp replaces them by the external map's",
                         me.brushes.size()));

    std::vector<std::string> warnings;
    const Placement placement = externalMapPlacement(e.keys, warnings);
    for (std::string& w : warnings) report(Severity::Warning, doc_.path, me.line, me.column, std::move(w));

    std::optional<dvec3> originBrush;
    size_t brushes = 0;
    for (const MapEntity& inner : external.entities) {
      // qbsp takes every brush of the prefab and no entity: nested prefabs are not followed,
      // which also keeps a prefab that includes itself (or its includer) from recursing.
      const std::string* innerClass = nullptr;
      for (const auto& [k, v] : inner.keys)
        if (equalsIgnoreCase(k, "classname")) {
          innerClass = &v;
          break;
        }
      if (innerClass && equalsIgnoreCase(*innerClass, "misc_external_map"))
        report(Severity::Note, external.path, inner.line, inner.column,
               "misc_external_map inside an external map is not followed (qbsp does not nest prefabs)");
      brushes += inner.brushes.size();
      if (auto centre = buildBrushes(inner.brushes, entityIndex, external.path, &placement)) originBrush = centre;
    }
    if (brushes == 0)
      report(Severity::Warning, doc_.path, me.line, me.column, fmt::format("misc_external_map: \"{}\" has no brushes", *name));

    // qbsp: the entity becomes the class the mapper asked for, its brushes already in place.
    if (const std::string* classname = e.find("_external_map_classname"); classname && !classname->empty())
      setKey(e.keys, "classname", *classname);
    else
      report(Severity::Warning, doc_.path, me.line, me.column,
             "misc_external_map without \"_external_map_classname\" (qbsp requires it); kept as misc_external_map");
    setKey(e.keys, "origin", "0 0 0");
    return originBrush;
  }

  // Hipnotic rotation: the origin of the entity named by "target" (qbsp's FixRotateOrigin).
  dvec3 rotatorOrigin(const Entity& rotator) {
    const std::string_view target = rotator.value("target");
    for (const Entity& other : scene_.entities) {
      if (target.empty() || !equalsIgnoreCase(other.value("targetname"), target)) continue;
      dvec3 origin;
      readVector(other.value("origin"), origin);
      return origin;
    }
    report(Severity::Warning, doc_.path, rotator.line, 0,
           fmt::format("'{}' has no origin brush and no target to rotate around; its origin is 0 0 0 (as in qbsp)", rotator.classname()));
    return dvec3(0.0);
  }

  // The brush's sides, one per plane; nullopt (with a warning) when the brush is skipped.
  std::optional<std::vector<Side>> brushSides(const MapBrush& mb, const std::string& file, const Placement* placement) {
    // Building a brush clips every face by every other one, so its cost grows with the square of
    // its faces: a few MB of faces on one brush would take minutes. Editors and compilers stay far
    // below this (Quake's qbsp allowed 32 faces a brush, LordHavoc's 256, qbsp3 128); the .bsp
    // reader draws the line at the same place.
    constexpr size_t kMaxBrushFaces = 1024;
    if (mb.faces.size() > kMaxBrushFaces) {
      report(Severity::Warning, file, mb.line, mb.column,
             fmt::format("brush skipped: it has {} faces, more than the {} a brush may have", mb.faces.size(), kMaxBrushFaces));
      return std::nullopt;
    }
    std::vector<Side> sides;
    sides.reserve(mb.faces.size());
    for (const MapFace& f : mb.faces) {
      const std::optional<Plane> written = planeFromPoints(f.points);
      // qbsp moves the three points and builds the plane again from them.
      const std::optional<Plane> plane = placement
          ? planeFromPoints({placement->apply(f.points[0]), placement->apply(f.points[1]), placement->apply(f.points[2])})
          : written;
      if (!written || !plane) {
        report(Severity::Warning, file, f.line, f.column, "face skipped: its three points are collinear (degenerate plane)");
        continue;
      }
      bool keep = true;
      for (const Side& s : sides) {
        if (samePlane(s.plane, *plane)) {
          report(Severity::Warning, file, f.line, f.column, fmt::format("face skipped: same plane as the face on line {}", s.face->line));
          keep = false;
          break;
        }
        if (samePlane(s.plane, plane->flipped())) {
          report(Severity::Warning, file, mb.line, mb.column,
                 fmt::format("brush skipped: faces on lines {} and {} are opposite on one plane (no volume)", s.face->line, f.line));
          return std::nullopt;
        }
      }
      if (keep) sides.push_back({&f, *plane, *written});
    }
    return sides;
  }

  // Whether the windings close a volume; a warning says why not.
  bool enclosesVolume(const std::vector<Winding>& windings, const MapBrush& mb, const std::string& file) {
    size_t withArea = 0;
    for (const Winding& w : windings) {
      if (w.size() < 3) continue;
      for (const dvec3& p : w) {
        // A corner out at the base square's reach: nothing clipped this side on that way.
        if (std::fabs(p.x) > kWorldExtent * 0.5 || std::fabs(p.y) > kWorldExtent * 0.5 || std::fabs(p.z) > kWorldExtent * 0.5) {
          report(Severity::Warning, file, mb.line, mb.column, "brush skipped: it is unbounded (its faces do not enclose a volume)");
          return false;
        }
      }
      ++withArea;
    }
    if (withArea < 4) {
      report(Severity::Warning, file, mb.line, mb.column, "brush skipped: it has no volume");
      return false;
    }
    return true;
  }

  Face faceFromSide(const Side& side, Winding winding, uint32_t brushIndex, const Placement* placement) {
    const MapFace& mf = *side.face;
    Face face;
    face.line = mf.line;
    face.brush = brushIndex;
    face.texture = mf.texture;
    face.material = materialFor(mf.texture);
    face.plane = side.plane;
    int width = 64, height = 64;
    if (loaded_ && face.material < loaded_->size()) {
      width = (*loaded_)[face.material].width;
      height = (*loaded_)[face.material].height;
    }
    TexVecs vecs;
    if (drawsNothing(mf)) {
      vecs = standardVecs(face.plane, {0.0, 0.0}, 0.0, {1.0, 1.0});
    } else {
      // The projection is made where the face was written, then moved with it (texture lock).
      vecs = faceTextureVecs(mf, side.written, width, height);
      if (placement) vecs = placement->apply(vecs);
    }
    face.frame = frameFromVecs(vecs, face.plane);
    face.surface = mf.surface;
    face.winding = std::move(winding);
    return face;
  }

  std::optional<uint32_t> buildBrush(const MapBrush& mb, uint32_t entityIndex, const std::string& file, const Placement* placement) {
    const std::optional<std::vector<Side>> sides = brushSides(mb, file, placement);
    if (!sides) return std::nullopt;
    std::vector<Plane> planes;
    for (const auto& side : *sides) planes.push_back(side.plane);
    std::vector<Winding> windings = brushWindings(planes);
    if (!enclosesVolume(windings, mb, file)) return std::nullopt;

    Brush brush;
    brush.line = mb.line;
    brush.entity = entityIndex;
    brush.firstFace = static_cast<uint32_t>(scene_.faces.size());
    const auto brushIndex = static_cast<uint32_t>(scene_.brushes.size());
    for (size_t i = 0; i < sides->size(); ++i) {
      const Side& side = (*sides)[i];
      if (windings[i].size() < 3) {
        // A plane that touches the brush in an edge or not at all: qbsp drops it too.
        report(Severity::Note, file, side.face->line, side.face->column, "face dropped: its plane does not touch the brush in an area");
        continue;
      }
      Face face = faceFromSide(side, std::move(windings[i]), brushIndex, placement);
      for (const dvec3& p : face.winding) brush.bounds.grow(p);
      scene_.faces.push_back(std::move(face));
    }
    brush.faceCount = static_cast<uint32_t>(scene_.faces.size()) - brush.firstFace;
    scene_.bounds.grow(brush.bounds);
    scene_.brushes.push_back(brush);
    return brushIndex;
  }

  // A patchDef2/patchDef3 (kept verbatim for the writer) tessellated as the Quake 3 engine
  // does (scene/curves.h) into a mesh of the entity. Its st are in texture units: texels are
  // st times the texture's size, known once the textures are loaded (importMap builds twice).
  void buildPatch(const MapBrush& mb, uint32_t entityIndex, const std::string& file, const Placement* placement) {
    std::string error;
    int lineOffset = 0;
    std::optional<MapPatch> patch = parsePatchBlock(mb.verbatim, error, lineOffset);
    if (patch && !(error = patchGridProblem(patch->control)).empty()) patch.reset();
    if (!patch) {
      report(Severity::Warning, file, mb.keywordLine + lineOffset, 0, "patch skipped: " + error);
      return;
    }
    Face model;
    model.line = mb.keywordLine;
    model.texture = patch->texture;
    model.material = materialFor(patch->texture);
    double width = 64.0, height = 64.0;
    if (loaded_ && model.material < loaded_->size()) {
      width = (*loaded_)[model.material].width;
      height = (*loaded_)[model.material].height;
    }
    for (PatchPoint& p : patch->control.points)
      if (placement) p.position = placement->apply(p.position);
    const PatchGrid grid = tessellatePatch(patch->control, curveMaxError_);
    scene_.meshes.push_back(Mesh{mb.keywordLine, entityIndex, MeshKind::Curve, static_cast<uint32_t>(scene_.faces.size()), 0, {}});
    auto vertex = [&](int row, int column) {
      const PatchPoint& p = grid.at(row, column);
      return MeshVertex{p.position, p.st.x * width, p.st.y * height};
    };
    for (int i = 0; i + 1 < grid.height; ++i)
      for (int j = 0; j + 1 < grid.width; ++j) {
        scene_.addMeshTriangle(vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), model);
        scene_.addMeshTriangle(vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1), model);
      }
    if (scene_.meshes.back().faceCount == 0) scene_.meshes.pop_back(); // a patch without area
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
  double curveMaxError_;
  Scene scene_;
  size_t verbatim_ = 0;
  std::unordered_map<std::string, uint32_t> materialIndex_;
};

} // namespace

Scene buildScene(const MapDocument& doc, const std::vector<Material>* loaded, double curveMaxError) {
  return SceneBuilder(doc, loaded, curveMaxError).build();
}

namespace {

// q3map2 lights a Quake 3 level from its shader scripts too (q3map_surfacelight, sky shaders):
// they lie in scripts/ of the level's game folder (the parent of its maps/) and the install,
// after the --textures folders, as the engine searches them. Returns one Material (no image)
// per texture the level's brushes and patches name, with its shader's light keys and its first
// stage's blend; nothing for other games. Read before the entities are told (ImportOptions::entitiesRead), so that the
// early kinds of light know the sky shaders' suns.
std::vector<Material> readShaderLight(const MapDocument& doc, const std::string& path, const ImportOptions& options,
                                      std::vector<std::string>& filesRead, Diagnostics& diagnostics) {
  const std::string format = toString(doc.dialect);
  if (!format.starts_with("quake3") && options.textures.game.game != "quake3") return {};
  std::vector<Material> materials;
  std::unordered_map<std::string, size_t> seen;
  auto add = [&](const std::string& texture) {
    if (seen.try_emplace(lowercase(texture), materials.size()).second) materials.emplace_back().name = texture;
  };
  for (const MapEntity& e : doc.entities)
    for (const MapBrush& b : e.brushes) {
      for (const MapFace& f : b.faces) add(f.texture);
      std::string error;
      int lineOffset = 0;
      if (b.kind == MapBrush::Kind::Verbatim && isPatchBlock(b.verbatim))
        if (const auto patch = parsePatchBlock(b.verbatim, error, lineOffset)) add(patch->texture);
    }
  const game::GameInstall install = game::openGameInstall(options.textures.game, path, format);
  bsp::GameFiles files;
  for (const std::string& dir : options.textures.textureDirs) files.addGameDir(dir, {".pk3"});
  for (const std::filesystem::path& dir : install.gameDirs) files.addGameDir(dir, {".pk3"});
  bsp::readQuake3ShaderLight(materials, bsp::readQuake3Shaders(files, diagnostics, &filesRead), files, diagnostics, &filesRead);
  return materials;
}

// The material of readShaderLight's named `name`, or null.
const Material* shaderLightOf(const std::vector<Material>& shaderLight, const std::string& name) {
  for (const Material& s : shaderLight)
    if (equalsIgnoreCase(name, s.name)) return &s;
  return nullptr;
}

// The light keys and blends read by readShaderLight, given to the built scene's materials by name.
void applyShaderLight(Scene& scene, const std::vector<Material>& shaderLight, const std::vector<std::string>& filesRead,
                      const Diagnostics& diagnostics) {
  if (shaderLight.empty()) return;
  for (Material& m : scene.materials)
    if (const Material* s = shaderLightOf(shaderLight, m.name)) {
      m.q3 = s->q3;
      m.blend = s->blend;
      // The engine draws a blended image's alpha by the blend alone, never as a mask.
      if (m.blend != ShaderBlend::Opaque) m.alphaTest = AlphaTest::None;
    }
  for (const Diagnostic& d : diagnostics) scene.diagnostics.push_back(d);
  for (const std::string& file : filesRead) scene.addInputFile(file);
}

} // namespace

Scene importMap(const std::string& path, const ImportOptions& options) {
  const MapDocument doc = readMapFile(path, options.dialect);
  std::vector<std::string> shaderFiles;
  Diagnostics shaderDiagnostics;
  const std::vector<Material> shaderLight = readShaderLight(doc, path, options, shaderFiles, shaderDiagnostics);
  Scene scene = buildScene(doc, nullptr, options.curveMaxError);
  if (options.entitiesRead) {
    // Told with the brushes and faces, before the textures: the early program start needs the
    // level's parts (lighting/render_scene.h LevelParts) beside its lights, and Quake 3's sky
    // shaders' suns need their light keys (applied again, with the blends, at the end).
    for (Material& m : scene.materials)
      if (const Material* s = shaderLightOf(shaderLight, m.name)) m.q3 = s->q3;
    options.entitiesRead(scene);
  }
  loadMaterials(scene, options.textures);
  loadSky(scene, options.textures);
  const bool inTextureUnits = std::any_of(doc.entities.begin(), doc.entities.end(), [](const MapEntity& e) {
    return std::any_of(e.brushes.begin(), e.brushes.end(), [](const MapBrush& b) {
      return b.kind == MapBrush::Kind::BrushDef || (b.kind == MapBrush::Kind::Verbatim && isPatchBlock(b.verbatim));
    });
  });
  if (!inTextureUnits) {
    applyShaderLight(scene, shaderLight, shaderFiles, shaderDiagnostics);
    return scene;
  }
  // brushDef matrices and patch st are in texture widths: now that the sizes are known, build
  // the frames again.
  // Materials come out in the same order, since the document is the same.
  Scene sized = buildScene(doc, &scene.materials, options.curveMaxError);
  sized.materials = std::move(scene.materials);
  sized.diagnostics = std::move(scene.diagnostics);
  sized.inputFiles = std::move(scene.inputFiles);
  applyShaderLight(sized, shaderLight, shaderFiles, shaderDiagnostics);
  return sized;
}

} // namespace bt::map
