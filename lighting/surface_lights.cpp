#include "lighting/surface_lights.h"

#include "lighting/qbsp_tjunc.h"
#include "lighting/render_scene.h"
#include "quake/bspfile_q2.h"

#include "scene/compiled_lighting.h"
#include "scene/names.h"
#include "scene/parallel_for.h"
#include "scene/winding.h"

#include <fmt/format.h>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <future>
#include <map>
#include <optional>

namespace bt {

namespace {

constexpr double kQ1SurfaceGrid = 128.0;        // `light -surflight_subdivide` default
constexpr double kRadiosityLift = 1.0;          // surflight.cc lifts a radiosity point 1 unit off the face
constexpr double kMinEmitterArea = 1.0;         // surflight.cc skips smaller faces
constexpr float kTextureGrey = 127.0f / 255.0f; // bounce.cc Face_LookupTextureColor without pixels

// The texture's mean colour in its own (sRGB) space, 0..1, as ericw-tools averages it.
glm::vec3 averageColor(const Image& image) {
  glm::dvec3 sum(0.0);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const uint8_t* p = image.texel(x, y);
      sum += glm::dvec3(p[0], p[1], p[2]);
    }
  return glm::vec3(sum / (255.0 * double(image.width) * double(image.height)));
}

dvec3 vertexMean(const Winding& w) {
  dvec3 sum(0.0);
  for (const dvec3& p : w) sum += p;
  return sum / double(w.size());
}

// Area-weighted centroid (ericw-tools' PolyCentroid); the vertex mean for a degenerate polygon.
dvec3 centroid(const Winding& w) {
  dvec3 sum(0.0);
  double totalArea = 0.0;
  for (size_t i = 1; i + 1 < w.size(); ++i) {
    const double a = glm::length(glm::cross(w[i] - w[0], w[i + 1] - w[0])) * 0.5;
    sum += a * (w[0] + w[i] + w[i + 1]) / 3.0;
    totalArea += a;
  }
  return totalArea > 0.0 ? sum / totalArea : vertexMean(w);
}

// The Q1 kind on one compiled face (light's GL_SubdivideSurface): a full copy of the template on
// every grid piece of it.
void addGridPoints(const Winding& compiledFace, const dvec3& normal, const SurfaceTemplate& t, std::vector<GpuLight>& out) {
  for (const Winding& piece : subdivideOnGrid(compiledFace, kQ1SurfaceGrid)) {
    GpuLight light = t.light;
    light.origin = glm::vec3(centroid(piece) + normal * double(t.offset));
    light.flags |= kLightFlagFromSurface;
    if (t.spotlight) light.direction = glm::vec3(normal);
    out.push_back(light);
  }
}

// The Q1 kind on a polygon rebuilt from the .map: points on the 128-unit grid of each face qbsp
// makes of `fragment` (its 240-texel subdivision, then, where `tjunc` is given, its T-junction
// fix against the world's vertices, `group` the polygon's weld group).
void addGridLights(const Face& face, const Winding& fragment, const SurfaceTemplate& t, const TJunctionVertices* tjunc, uint32_t group,
                   std::vector<GpuLight>& out) {
  std::vector<Winding> qbspPieces;
  subdivideForQbsp(fragment, face.frame, qbspPieces);
  if (tjunc) {
    std::vector<Winding> fixed;
    for (const Winding& w : qbspPieces)
      for (const Winding& piece : fixTJunctions(w, group, *tjunc)) fixed.push_back(withoutColinearPoints(piece));
    qbspPieces = std::move(fixed);
  }
  for (const Winding& qbspPiece : qbspPieces) {
    addGridPoints(qbspPiece, face.plane.normal, t, out);
    if (out.size() > kMaxSurfaceLights) return; // the caller cuts the list and says so
  }
}

// The radiosity kind: one point for the whole face, value x area, falling off as 1/d^2.
void addRadiosityLight(const Scene& scene, const Face& face, const Winding& fragment, const SurfaceTemplate& t, const WorldLighting& world,
                       std::vector<GpuLight>& out) {
  const double faceArea = area(fragment);
  if (faceArea < kMinEmitterArea) return;
  const dvec3 origin = vertexMean(fragment) + face.plane.normal * kRadiosityLift;

  // surflight.cc: colour (0..1) x light value; its brightest channel is the intensity, and the
  // colour is normalised by it only when that is above 1.
  glm::vec3 color = t.light.color;
  if (!t.hasColor && face.material < scene.materials.size()) {
    // Face_LookupTextureColor: a texture the compiler cannot find is an image without pixels,
    // whose mean is black (light_q2_emissive_cube's SURF_LIGHT faces light nothing); one it
    // found without pixels is 127 grey.
    const Material& m = scene.materials[face.material];
    color = m.missing() ? glm::vec3(0.0f) : m.baseColor.empty() ? glm::vec3(kTextureGrey) : averageColor(m.baseColor);
  }
  color *= t.light.value;
  const float intensity = std::max({color.x, color.y, color.z});
  if (intensity <= 0.0f) return; // ericw-tools has no negative surface lights
  if (intensity > 1.0f) color /= intensity;

  GpuLight light;
  light.type = uint32_t(LightType::Point);
  light.formula = uint32_t(LightFormula::SurfaceRadiosity);
  light.origin = glm::vec3(origin);
  light.direction = glm::vec3(face.plane.normal);
  light.color = color;
  light.value = intensity * float(faceArea) * world.surflightScale;
  light.anglescale = 0.5f; // the receiver's (0.5 + 0.5 cos): ericw-tools' "rescale"
  light.flags = (t.light.flags & ~kLightFlagBleed) | kLightFlagFromSurface;
  out.push_back(light);
}

} // namespace

// The `_surflight_group` of entity `e`'s model (0 when unset): a template lights only the faces of
// its own group (ericw-tools' surface light groups). func_detail and func_group are merged into
// the world by qbsp, and their keys with them: the world's group, 0 (q1_light_surflight_group: a
// func_detail with group 1 glows with the group-0 template).
static int entityLightGroup(const Scene& scene, uint32_t e) {
  if (e >= scene.entities.size()) return 0;
  const Entity& entity = scene.entities[e];
  if (mergedIntoWorld(entity.classname())) return 0;
  return std::atoi(std::string(entity.value("_surflight_group", "0")).c_str());
}

static int surfaceLightGroup(const Scene& scene, uint32_t face) {
  const uint32_t brush = scene.faces[face].brush;
  return brush >= scene.brushes.size() ? 0 : entityLightGroup(scene, scene.brushes[brush].entity);
}

// A compiled Quake 1 / Half-Life level's own faces, as `light` reads them, where the .bsp import
// has them (Scene::compiledLighting): the scene's brushes of such a level are its leaves' cells,
// not the mapper's brushes, so rebuilding qbsp's faces from them would guess at what the file says.
static bool hasCompiledFaces(const Scene& scene) {
  const CompiledLighting* cl = scene.compiledLighting.get();
  return cl && (cl->engine == "quake" || cl->engine == "hexen2" || cl->engine == "halflife");
}

// The points `light` makes of the compiled faces: the Q1 kind on the faces its MakeSurfaceLights
// takes (LightmappedFace::takesSurfaceLights), each on the 128-unit grid as it stands (qbsp has
// cut it already); the radiosity kind on every face with the texture (MakeRadiositySurfaceLights
// walks all faces), from its points without those where it goes straight on (remove_colinear).
static std::vector<GpuLight> compiledFaceLights(const Scene& scene, const std::vector<SurfaceTemplate>& templates,
                                                const WorldLighting& world, Diagnostics& diagnostics) {
  std::vector<GpuLight> lights;
  for (const SurfaceTemplate& t : templates)
    for (const LightmappedFace& lf : scene.compiledLighting->faces) {
      if (lf.polygon.size() < 3 || !equalsIgnoreCase(lf.texture, t.texture) || entityLightGroup(scene, lf.entity) != t.group) continue;
      if (!t.radiosity) {
        if (lf.takesSurfaceLights) addGridPoints(lf.polygon, lf.normal, t, lights);
      } else {
        Face face;
        face.plane = Plane{lf.normal, glm::dot(lf.normal, lf.polygon.front())};
        face.material = scene.findMaterial(lf.texture).value_or(uint32_t(scene.materials.size()));
        addRadiosityLight(scene, face, withoutColinearPoints(lf.polygon), t, world, lights);
      }
      if (lights.size() > kMaxSurfaceLights) {
        lights.resize(kMaxSurfaceLights);
        diagnostics.push_back(
            {Severity::Warning, scene.sourcePath, 0, 0,
             fmt::format("_surface \"{}\": more than {} surface light points; the rest are left out", t.texture, kMaxSurfaceLights)});
        return lights;
      }
    }
  return lights;
}

namespace {

// Coplanar sides with one texture projection: qbsp merges the faces of its portals on a node
// only within one texinfo (TryMerge), and across the sides of different brushes within one.
bool sameSurface(const Face& a, const Face& b) {
  auto near = [](const dvec3& p, const dvec3& q) { return glm::length(p - q) < 1e-4; };
  return near(a.plane.normal, b.plane.normal) && std::abs(a.plane.dist - b.plane.dist) < kOnPlaneEpsilon &&
      near(a.frame.tangent, b.frame.tangent) && near(a.frame.bitangent, b.frame.bitangent) &&
      std::abs(a.frame.s(a.frame.origin) - a.frame.s(b.frame.origin)) < 1e-3 &&
      std::abs(a.frame.t(a.frame.origin) - a.frame.t(b.frame.origin)) < 1e-3;
}

// The vertices of the world faces qbsp writes with `tree` that reach some box of `near` (the
// ones that look into the void removed), for its T-junction fix of the faces in those boxes: a
// face far from them puts no vertex on their edges. `near` comes in groups (a surface's faces),
// each with the box around all of its own, so that most faces are turned away by a few boxes.
struct NearGroup {
  Bounds all;
  std::vector<Bounds> boxes;
};

TJunctionVertices worldVertices(const Scene& scene, const std::vector<BrushContents>& contents, const QbspTree& tree, const VoidTest& voids,
                                const std::vector<NearGroup>& near) {
  auto touches = [](const Bounds& a, const Bounds& b) {
    return glm::all(glm::lessThanEqual(a.min, b.max)) && glm::all(glm::lessThanEqual(b.min, a.max));
  };
  // What CSG keeps of each side near the templates, on all cores.
  std::vector<std::vector<Winding>> fragments(scene.faces.size());
  parallelFor(scene.faces.size(), 0, [&](size_t f) {
    const uint32_t b = scene.faces[f].brush;
    if (b >= contents.size() || contents[b] == BrushContents::Empty) return;
    Bounds bounds;
    for (const dvec3& p : scene.faces[f].winding) bounds.grow(p);
    const bool reaches = std::any_of(near.begin(), near.end(), [&](const NearGroup& g) {
      return touches(g.all, bounds) && std::any_of(g.boxes.begin(), g.boxes.end(), [&](const Bounds& n) { return touches(n, bounds); });
    });
    if (reaches) fragments[f] = visibleFragments(scene, uint32_t(f), contents);
  });
  // The sides gathered into surfaces (one texture, projection and weld group), whose faces
  // merge across brushes as qbsp's do: a wall of several brushes is one face where their sides
  // share a texinfo (testsurfacelight's func_detail wall on x -64, y -80..0), so its
  // subdivision and its vertices are the compiler's. Buckets by plane keep the search short.
  std::map<std::pair<int64_t, int64_t>, std::vector<size_t>> buckets; // rounded distance, normal's largest axis
  struct WorldSurface {
    std::vector<uint32_t> sides; // the first gives plane, frame and texture
    uint32_t weldGroup;
  };
  std::vector<WorldSurface> surfaces;
  for (uint32_t f = 0; f < scene.faces.size(); ++f) {
    if (fragments[f].empty()) continue;
    const Face& face = scene.faces[f];
    const dvec3 a = glm::abs(face.plane.normal);
    const int64_t axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
    std::vector<size_t>& bucket = buckets[{std::llround(face.plane.dist), axis * 2 + (face.plane.normal[axis] > 0.0)}];
    const uint32_t group = quake1WeldGroup(scene, contents, face.brush);
    const auto it = std::find_if(bucket.begin(), bucket.end(), [&](size_t s) {
      const Face& other = scene.faces[surfaces[s].sides.front()];
      return surfaces[s].weldGroup == group && sameSurface(other, face) && equalsIgnoreCase(other.texture, face.texture);
    });
    if (it != bucket.end()) {
      surfaces[*it].sides.push_back(f);
    } else {
      bucket.push_back(surfaces.size());
      surfaces.push_back({{f}, group});
    }
  }
  std::vector<std::vector<Winding>> kept(surfaces.size());
  parallelFor(surfaces.size(), 0, [&](size_t s) {
    const std::vector<uint32_t>& sides = surfaces[s].sides;
    std::vector<Winding> surfaceFragments;
    for (uint32_t f : sides) surfaceFragments.insert(surfaceFragments.end(), fragments[f].begin(), fragments[f].end());
    const Face& face = scene.faces[sides.front()];
    std::vector<Winding> pieces;
    for (const Winding& w : compilerFaces(scene, sides, surfaceFragments, contents, tree)) subdivideForQbsp(w, face.frame, pieces);
    for (Winding& w : pieces)
      if (!voids.inVoid(vertexMean(w) + face.plane.normal * kVoidProbeDistance)) kept[s].push_back(std::move(w));
  });
  TJunctionVertices vertices;
  for (size_t s = 0; s < surfaces.size(); ++s)
    for (const Winding& w : kept[s]) vertices.add(w, surfaces[s].weldGroup);
  return vertices;
}

} // namespace

std::vector<GpuLight> spreadSurfaceLights(const Scene& scene, const std::vector<SurfaceTemplate>& templates,
                                          const std::vector<BrushContents>& contents, const QbspTree& worldTree, const WorldLighting& world,
                                          const TraceScene& tracer, Diagnostics& diagnostics) {
  if (templates.empty()) return {};
  if (hasCompiledFaces(scene)) return compiledFaceLights(scene, templates, world, diagnostics);
  // The void test traces rays from every point entity (thousands on a large level); the
  // surfaces' CSG below does not need it, so it runs beside them.
  std::future<VoidTest> voidTest = std::async(std::launch::async, [&] { return VoidTest(scene, tracer); });
  // qbsp makes its faces of what CSG leaves of the coplanar sides with one texture and
  // projection (compilerFaces); the compiler spreads its lights over those faces.
  struct Surface {
    const SurfaceTemplate* light;
    std::vector<uint32_t> sides; // the first gives plane, frame, material
    std::vector<Winding> polygons;
  };
  std::vector<Surface> surfaces; // template by template
  for (const SurfaceTemplate& t : templates) {
    const size_t first = surfaces.size();
    for (uint32_t f = 0; f < scene.faces.size(); ++f) {
      if (scene.faces[f].brush == kNoBrush || !equalsIgnoreCase(scene.faces[f].texture, t.texture)) continue; // meshes: no compiled faces
      if (surfaceLightGroup(scene, f) != t.group) continue;
      if (t.q2Value &&
          !(scene.faces[f].surface && (scene.faces[f].surface->flags & quake::q2::SURF_LIGHT) &&
            scene.faces[f].surface->value == *t.q2Value))
        continue;
      std::vector<Winding> fragments = visibleFragments(scene, f, contents);
      if (fragments.empty()) continue;
      auto it = std::find_if(surfaces.begin() + std::ptrdiff_t(first), surfaces.end(),
                             [&](const Surface& s) { return sameSurface(scene.faces[s.sides.front()], scene.faces[f]); });
      if (it == surfaces.end()) it = surfaces.insert(surfaces.end(), Surface{&t, {}, {}});
      it->sides.push_back(f);
      for (Winding& w : fragments) it->polygons.push_back(std::move(w));
    }
  }
  const VoidTest inVoid = voidTest.get();
  // A Quake 1 template's faces are cut by the compiler's tree of the whole world
  // (quake1WorldTree), then at their T-junctions; Quake 2's tree is the one the caller gives.
  std::vector<Winding> templateFaces;
  for (const Surface& surface : surfaces) templateFaces.insert(templateFaces.end(), surface.polygons.begin(), surface.polygons.end());
  const QbspTree quake1Tree =
      gameOf(scene) == Game::Quake ? quake1WorldTree(scene, contents, inVoid, std::move(templateFaces)) : QbspTree();
  const QbspTree& tree = quake1Tree.nodes().empty() ? worldTree : quake1Tree;
  // Each surface's faces depend on nothing else: the surfaces are shared among threads.
  parallelFor(surfaces.size(), 0,
              [&](size_t i) { surfaces[i].polygons = compilerFaces(scene, surfaces[i].sides, surfaces[i].polygons, contents, tree); });
  std::optional<TJunctionVertices> tjunctions;
  if (!quake1Tree.nodes().empty()) {
    std::vector<NearGroup> near;
    for (const Surface& surface : surfaces) {
      NearGroup& group = near.emplace_back();
      for (const Winding& w : surface.polygons) {
        Bounds b;
        for (const dvec3& p : w) b.grow(p);
        group.boxes.push_back(Bounds{b.min - dvec3(kOnPlaneEpsilon), b.max + dvec3(kOnPlaneEpsilon)});
        group.all.grow(group.boxes.back());
      }
    }
    tjunctions = worldVertices(scene, contents, quake1Tree, inVoid, near);
  }

  std::vector<GpuLight> lights;
  for (const Surface& surface : surfaces) {
    const SurfaceTemplate& t = *surface.light;
    const Face& face = scene.faces[surface.sides.front()];
    const bool liquid = face.brush < contents.size() && contents[face.brush] == BrushContents::Liquid;
    for (const Winding& polygon : surface.polygons) {
      if (inVoid.inVoid(centroid(polygon) + face.plane.normal * kVoidProbeDistance)) continue;
      if (!t.radiosity) {
        addGridLights(face, polygon, t, tjunctions ? &*tjunctions : nullptr, quake1WeldGroup(scene, contents, face.brush), lights);
      } else {
        addRadiosityLight(scene, face, polygon, t, world, lights);
        // qbsp gives a liquid surface a second face looking into the liquid; the Q1 kind skips
        // it ("underwater side"), the radiosity kind emits from it too.
        if (liquid) {
          Face underwater = face;
          underwater.plane = face.plane.flipped();
          addRadiosityLight(scene, underwater, Winding(polygon.rbegin(), polygon.rend()), t, world, lights);
        }
      }
      if (lights.size() > kMaxSurfaceLights) {
        lights.resize(kMaxSurfaceLights);
        diagnostics.push_back(
            {Severity::Warning, scene.sourcePath, face.line, 0,
             fmt::format("_surface \"{}\": more than {} surface light points; the rest are left out", t.texture, kMaxSurfaceLights)});
        return lights;
      }
    }
  }
  return lights;
}

} // namespace bt
