// The raw contents of a compiled BSP file, every lump bounds-checked and every index validated.
//
// One struct holds all six versions the importer understands; fields a version lacks stay empty.
// Records are widened to one in-memory layout (BSP29's int16 fields become int32, ...), so the
// code that builds a Scene never cares which version it reads. Layouts follow the reference
// compiler's bspfile.h (ericw-tools) and id's released sources (qfiles.h for Quake 2 and 3).
//
// After readBspFile returns, every index stored in these tables is in range for the table it
// refers to (plane, edge, vertex, texinfo, miptex, node, leaf, face, brush, side, shader,
// draw vertex), so callers may index without checks. Byte offsets into the lighting lump are
// not validated here (their extent depends on face size): check them where they are used.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace bt::bsp {

enum class Version {
  Bsp29,      // Quake (and Hexen II, see BspFile::hexen2Models)
  Bsp2,       // "BSP2": Quake with 32-bit indices and float bounds (large maps)
  Bsp2rmq,    // "2PSB": RMQ's first 32-bit variant, int16 bounds
  HalfLife30, // Half-Life: BSP29 layout, miptex carry their own palette, RGB lighting
  Quake2_38,  // "IBSP" 38
  Quake3_46,  // "IBSP" 46
};

// "bsp29", "bsp2", "2psb", "bsp30", "ibsp38", "ibsp46": the Scene::format of each version.
const char* toString(Version version);

// Plane as stored: Q1/Q2 store a type (axial or not), Q3 stores planes in pairs (i ^ 1 is the
// flipped one) without a type.
struct BspPlane {
  glm::vec3 normal{0.0f};
  float dist = 0.0f;
  int32_t type = 0;
};

// Texture projection of a face. For Q1/HL `texture` is the name of miptex[miptex] ("" when the
// miptex slot is empty); for Q2 it is the name stored in the texinfo and miptex is -1.
// Texel s = dot(p, vecs[0].xyz) + vecs[0].w, t likewise with vecs[1].
struct TexInfo {
  std::array<std::array<float, 4>, 2> vecs{};
  int32_t flags = 0;
  std::string texture;
  int32_t value = 0;        // Q2 surface value (light emission)
  int32_t miptex = -1;      // Q1/HL index into BspFile::miptex
  int32_t nextTexinfo = -1; // Q2 animation chain, -1 ends it
};

// Q1/Q2 face (Q3 has draw surfaces instead, see Surface).
struct Face {
  int32_t plane = 0;
  int32_t side = 0; // nonzero: the face looks along -plane.normal
  int32_t firstEdge = 0;
  int32_t edgeCount = 0;
  int32_t texinfo = 0;
  std::array<uint8_t, 4> styles{255, 255, 255, 255}; // 255 ends the list
  int32_t lightOffset = -1;                          // byte offset into lighting, -1 = none
};

// A Q1/HL texture in the miptex lump. `bytes` is the whole record from its header on, cut at the
// next record or the lump end: what a miptex decoder needs (Half-Life appends a palette).
struct Miptex {
  std::string name;
  uint32_t width = 0;
  uint32_t height = 0;
  bool present = false;   // false: the directory slot is -1 (texture left out)
  bool hasPixels = false; // false: qbsp -notex / external (WAD) texture
  std::vector<uint8_t> bytes;
};

// A BSP tree node. children[i] >= 0 is a node; < 0 is leaf (-1 - children[i]).
struct Node {
  int32_t plane = 0;
  std::array<int32_t, 2> children{};
  int32_t firstFace = 0;
  int32_t faceCount = 0;
};

struct Leaf {
  int32_t contents = 0; // Q1 CONTENTS_* (negative) or Q2 contents bits; Q3: 0
  int32_t cluster = -1; // Q1 visofs, Q2/Q3 cluster
  int32_t area = 0;
  int32_t firstLeafFace = 0; // into leafFaces (Q1 marksurfaces, Q3 leafsurfaces)
  int32_t leafFaceCount = 0;
  int32_t firstLeafBrush = 0; // into leafBrushes (Q2/Q3)
  int32_t leafBrushCount = 0;
};

// Q1/HL clip hull node; children < 0 are contents (CONTENTS_EMPTY = -1, CONTENTS_SOLID = -2).
struct ClipNode {
  int32_t plane = 0;
  std::array<int32_t, 2> children{};
};

struct Model {
  glm::vec3 mins{0.0f}, maxs{0.0f}, origin{0.0f};
  std::array<int32_t, 8> headNode{}; // Q1: 4 hulls (Hexen II 8), [0] = node tree; Q2: [0] only
  int32_t visLeafs = 0;
  int32_t firstFace = 0; // Q3: first draw surface
  int32_t faceCount = 0;
  int32_t firstBrush = 0; // Q3 only (Q2 reaches its brushes through the leafs)
  int32_t brushCount = 0;
};

// Q2/Q3 brush: Q2 `contents`, Q3 `shader` (index into shaders).
struct Brush {
  int32_t firstSide = 0;
  int32_t sideCount = 0;
  int32_t contents = 0;
  int32_t shader = -1;
};

// Q2: texinfo (-1 = none); Q3: shader.
struct BrushSide {
  int32_t plane = 0;
  int32_t texinfo = -1;
  int32_t shader = -1;
};

// Quake 3 tables.
struct Shader {
  std::string name;
  int32_t surfaceFlags = 0;
  int32_t contentFlags = 0;
};

struct DrawVertex {
  glm::vec3 position{0.0f};
  glm::vec2 st{0.0f}; // texture coordinates, in texture widths (not texels)
  glm::vec2 lightmap{0.0f};
  glm::vec3 normal{0.0f};
  std::array<uint8_t, 4> color{};
};

enum class SurfaceType : int32_t { Bad = 0, Planar = 1, Patch = 2, TriangleSoup = 3, Flare = 4 };

struct Surface {
  int32_t shader = 0;
  int32_t fog = -1;
  SurfaceType type = SurfaceType::Bad;
  int32_t firstVertex = 0;
  int32_t vertexCount = 0;
  int32_t firstIndex = 0; // into drawIndices; each index is relative to firstVertex
  int32_t indexCount = 0;
  int32_t lightmap = -1;
  std::array<int32_t, 2> lightmapCorner{};
  std::array<int32_t, 2> lightmapSize{};
  glm::vec3 lightmapOrigin{0.0f};
  std::array<glm::vec3, 3> lightmapVecs{}; // [2] is the plane normal of a planar surface
  std::array<int32_t, 2> patchSize{};
};

// An extension lump from the BSPX directory that ericw-tools appends after the Q1 or Q2 lumps
// (BRUSHLIST, RGBLIGHTING, LMSHIFT, DECOUPLED_LM, ...).
struct BspxLump {
  std::string name;
  std::vector<uint8_t> bytes;
};

struct BspFile {
  Version version = Version::Bsp29;
  bool hexen2Models = false; // BSP29 with Hexen II's 8-hull models
  std::string path;

  std::string entities; // the entities lump text, NUL cut off
  std::vector<BspPlane> planes;
  std::vector<glm::vec3> vertices;
  std::vector<std::array<uint32_t, 2>> edges;
  std::vector<int32_t> surfedges; // >= 0: edge in order, < 0: edge -i reversed
  std::vector<Face> faces;
  std::vector<TexInfo> texinfo;
  std::vector<Miptex> miptex;
  std::vector<Model> models;
  std::vector<Node> nodes;
  std::vector<Leaf> leafs;
  std::vector<int32_t> leafFaces;   // Q1 marksurfaces, Q2 leaffaces, Q3 leafsurfaces
  std::vector<int32_t> leafBrushes; // Q2/Q3
  std::vector<ClipNode> clipNodes;  // Q1/HL
  std::vector<Brush> brushes;       // Q2/Q3
  std::vector<BrushSide> brushSides;
  std::vector<uint8_t> lighting; // Q1: 1 byte per luxel; HL/Q2: RGB
  std::vector<uint8_t> visibility;

  // Quake 3
  std::vector<Shader> shaders;
  std::vector<DrawVertex> drawVertices;
  std::vector<int32_t> drawIndices;
  std::vector<Surface> surfaces;
  std::vector<uint8_t> lightmaps; // 128 x 128 RGB pages

  std::vector<BspxLump> bspx;

  // The polygon of Q1/Q2 face `face`, vertices in the order the file stores them (clockwise seen
  // from the side the face looks at, Quake's convention).
  std::vector<glm::dvec3> faceVertices(size_t face) const;
  // The texture name of Q1/Q2 face `face`.
  std::string_view faceTexture(size_t face) const;
  // The BSPX lump called name, or nullptr.
  const BspxLump* findBspx(std::string_view name) const;
  bool isQuake1Family() const {
    return version == Version::Bsp29 || version == Version::Bsp2 || version == Version::Bsp2rmq || version == Version::HalfLife30;
  }
};

// Parses a whole BSP file. Throws ImportError naming pathForErrors and the lump at fault when
// the file is truncated, a lump lies outside the file, a size or count is impossible, or an
// index is out of range.
BspFile readBspFile(std::span<const uint8_t> bytes, const std::string& pathForErrors);
BspFile readBspFile(const std::filesystem::path& path);

} // namespace bt::bsp
