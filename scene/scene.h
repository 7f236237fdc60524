// The scene model: what every importer produces and every renderer consumes.
//
// A Scene is format-neutral. A .map file and the .bsp compiled from it import to the same
// kind of Scene: entities with their keys, brushes as convex sets of planes, and for every
// brush side a Face with its plane, its polygon (winding) and its texture frame.
//
// Units and conventions are Quake's: one unit is one texel at scale 1, +Z is up, a plane's
// normal points out of its brush, and a point p lies on the plane when dot(normal, p) == dist.
#pragma once

#include "scene/diagnostics.h"
#include "scene/material.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace bt {

using dvec3 = glm::dvec3;

struct Plane {
  dvec3 normal{0.0, 0.0, 1.0};
  double dist = 0.0;

  double distanceTo(const dvec3& p) const { return normal.x * p.x + normal.y * p.y + normal.z * p.z - dist; }
  Plane flipped() const { return {-normal, -dist}; }
};

struct Bounds {
  dvec3 min{std::numeric_limits<double>::infinity()};
  dvec3 max{-std::numeric_limits<double>::infinity()};

  bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  void grow(const dvec3& p);
  void grow(const Bounds& b);
  dvec3 center() const { return (min + max) * 0.5; }
  dvec3 extent() const { return max - min; }
  double surfaceArea() const;
};

// The texture frame of a face, in texels:
//   s = dot(p - origin, tangent),  t = dot(p - origin, bitangent)
// equals the texture coordinates that qbsp writes into texinfo for that face:
//   texinfo.vecs[0] = (tangent, -dot(origin, tangent)), vecs[1] = (bitangent, -dot(origin, bitangent)).
// tangent and bitangent are not unit vectors: their length is 1 / texture scale.
// origin is chosen on the face plane so that the frame is unique.
struct TextureFrame {
  dvec3 origin{0.0};
  dvec3 tangent{1.0, 0.0, 0.0};
  dvec3 bitangent{0.0, 1.0, 0.0};

  double s(const dvec3& p) const;
  double t(const dvec3& p) const;
};

// Quake 2 / Quake 3 per-face surface attributes (contents, surface flags and value).
struct SurfaceAttributes {
  int32_t contents = 0;
  int32_t flags = 0;
  double value = 0.0;
  bool operator==(const SurfaceAttributes&) const = default;
};

// Face::brush of a mesh triangle's face: it belongs to no brush (Scene::meshes holds it).
inline constexpr uint32_t kNoBrush = 0xffffffffu;

struct Face {
  int line = 0;          // 1-based source line of the face, 0 when the source has no lines (BSP)
  uint32_t brush = 0;    // index into Scene::brushes, or kNoBrush for a mesh triangle
  uint32_t material = 0; // index into Scene::materials
  std::string texture;
  Plane plane;
  TextureFrame frame;
  std::optional<SurfaceAttributes> surface;
  std::vector<dvec3> winding; // convex polygon on the plane, counter-clockwise seen from outside
};

struct Brush {
  int line = 0;
  uint32_t entity = 0;
  uint32_t firstFace = 0; // faces [firstFace, firstFace + faceCount) of Scene::faces
  uint32_t faceCount = 0;
  Bounds bounds; // from the windings
};

// A triangle mesh: a Quake 3 curve (patchDef2/3, an IBSP patch) tessellated, or an IBSP triangle
// soup. Each triangle is two faces of Scene::faces, one per side, so that everything keyed by
// face (materials, classes, AOV face ids) works on it unchanged and every hit meets a face whose
// plane faces the ray, as a brush face does:
//   faces[firstFace + 2k]     the front side: winding (a, b, c) counter-clockwise seen from the
//                             front, plane normal = normalize(cross(b - a, c - a));
//   faces[firstFace + 2k + 1] the back side: winding (a, c, b), the plane flipped.
// Both have brush = kNoBrush, the mesh's material and a texture frame (in the triangle's plane)
// that reproduces the vertices' st exactly: st interpolated barycentrically is affine on the plane.
// Scene::meshes lie in the order of their faces. A Model is one skin's triangles of an entity
// model (importers/models/entity_models.h), placed at its point entity.
enum class MeshKind : uint8_t { Curve, TriangleSoup, Model };

struct Mesh {
  int line = 0; // the patchDef's (a model's: its entity's) line in a .map, 0 for a .bsp
  uint32_t entity = 0;
  MeshKind kind = MeshKind::Curve;
  uint32_t firstFace = 0; // faces [firstFace, firstFace + faceCount) of Scene::faces
  uint32_t faceCount = 0; // two per triangle
  Bounds bounds;
};

struct MeshVertex {
  dvec3 position{0.0};
  double s = 0.0, t = 0.0; // texture coordinates in texels
};

struct Entity {
  int line = 0;
  std::vector<std::pair<std::string, std::string>> keys; // file order, duplicates kept
  uint32_t firstBrush = 0;                               // brushes [firstBrush, firstBrush + brushCount) of Scene::brushes
  uint32_t brushCount = 0;

  std::string_view classname() const;
  // The first value for key, or nullptr. Quake's engine takes the last duplicate while
  // qbsp takes the first; the first is what every tool that reads .map sources agrees on.
  const std::string* find(std::string_view key) const;
  std::string_view value(std::string_view key, std::string_view fallback = {}) const;
};

struct CompiledLighting; // scene/compiled_lighting.h

// The images a level's sky faces show by the ray's direction, the same on every sky face, as
// the engine draws its sky (lighting/sky.h): Quake's two layers or a sky box. They are the
// materials from `firstMaterial` on, materials no face uses: the layers back then front; the
// box's sides in the order of their suffixes rt, bk, lf, ft, up, dn (the engines' `suf`).
struct Sky {
  // Quake's two layers: back, then front (its index 0 clear); six sides pulled in by half a
  // texel (QuakeSpasm, Quake 2); six sides clamped to their edge texels (Quake 3: sky_min 0,
  // sky_max 1, GL_CLAMP_TO_EDGE).
  enum class Kind : uint32_t { QuakeLayers = 1, Box = 2, BoxClamped = 3 };
  Kind kind = Kind::QuakeLayers;
  std::string name; // the sky box's name ("mysky" for gfx/env/mysky{rt,...}.tga), or the sky texture's
  uint32_t firstMaterial = 0;
};

struct Scene {
  std::string sourcePath;
  std::string format; // map dialect ("standard", "valve220", ...) or BSP version ("bsp29", ...)
  std::string game;   // the game profile `--game` names (quake, halflife, quake2, ...); empty: told by the level
  std::vector<Entity> entities;
  std::vector<Brush> brushes;
  std::vector<Face> faces;
  std::vector<Mesh> meshes;        // curves and triangle soups, see Mesh
  std::vector<Material> materials; // one per distinct texture name, see material.h
  Bounds bounds;                   // of all brushes and meshes
  Diagnostics diagnostics;         // everything the importer skipped or could not resolve
  // The lightmaps a compiler baked into a .bsp (null for .map sources), for a view mode that
  // shows them beside the path-traced preview. See scene/compiled_lighting.h.
  std::shared_ptr<const CompiledLighting> compiledLighting;
  // Every file the import read, the level first: prefab .maps (misc_external_map), WADs,
  // palettes, Quake 3 shader scripts, each texture image and companion map (a .pk3 for what
  // came out of one). `brushtrace view` reloads when any of them is saved.
  std::vector<std::string> inputFiles;
  std::optional<Sky> sky; // where the level has sky images (importers/textures loadSky)

  const Entity* worldspawn() const;
  // The entity a face belongs to, through its brush or its mesh; entities.size() if none.
  uint32_t faceEntity(uint32_t face) const;
  // Appends triangle (a, b, c) to the last mesh as its two faces (see Mesh), with `model` as
  // the faces' texture, material and surface attributes. A triangle without area is skipped
  // (false): it has no plane, and no ray can see it.
  bool addMeshTriangle(const MeshVertex& a, const MeshVertex& b, const MeshVertex& c, const Face& model);
  // Appends `path` to inputFiles unless it is listed already.
  void addInputFile(const std::string& path) {
    if (std::find(inputFiles.begin(), inputFiles.end(), path) == inputFiles.end()) inputFiles.push_back(path);
  }
  // Index of the material called name, or std::nullopt. Case-insensitive like Quake.
  std::optional<uint32_t> findMaterial(std::string_view name) const;
};

} // namespace bt
