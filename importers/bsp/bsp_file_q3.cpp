// Quake 3's BSP files: IBSP 46. Layout as id's qfiles.h (q3map2's bspfile_abstract).
#include "importers/bsp/bsp_lumps.h"

namespace bt::bsp::detail {

namespace {

namespace q3 {
enum : int {
  Entities,
  Shaders,
  Planes,
  Nodes,
  Leafs,
  LeafSurfaces,
  LeafBrushes,
  Models,
  Brushes,
  BrushSides,
  DrawVerts,
  DrawIndexes,
  Fogs,
  Surfaces,
  Lightmaps,
  LightGrid,
  Visibility,
  Count
};
constexpr const char* kNames[Count] = {"entities",    "shaders",  "planes",    "nodes",      "leafs",     "leafsurfaces",
                                       "leafbrushes", "models",   "brushes",   "brushsides", "drawverts", "drawindexes",
                                       "fogs",        "surfaces", "lightmaps", "lightgrid",  "visibility"};
} // namespace q3

// The lumps from entities to brush sides, in the file's order (so that of two bad lumps the
// first is the one reported).
void readQuake3EntitiesToBrushSides(const Reader& reader, std::span<const Lump> L, BspFile& bsp) {
  bsp.entities = entitiesText(L[q3::Entities]);
  bsp.shaders = reader.records<Shader>(L[q3::Shaders], 72, [](FieldReader& r) {
    Shader s;
    s.name = r.name(64);
    s.surfaceFlags = r.i32();
    s.contentFlags = r.i32();
    return s;
  });
  bsp.planes = reader.records<BspPlane>(L[q3::Planes], 16, [](FieldReader& r) {
    BspPlane p;
    p.normal = r.vec3();
    p.dist = r.f32();
    return p;
  });
  bsp.nodes = reader.records<Node>(L[q3::Nodes], 36, [](FieldReader& r) {
    Node n;
    n.plane = r.i32();
    n.children = {r.i32(), r.i32()};
    return n; // int32 bounds follow; Q3 nodes carry no faces
  });
  bsp.leafs = reader.records<Leaf>(L[q3::Leafs], 48, [](FieldReader& r) {
    Leaf l;
    l.cluster = r.i32();
    l.area = r.i32();
    r.skip(24);
    l.firstLeafFace = r.i32();
    l.leafFaceCount = r.i32();
    l.firstLeafBrush = r.i32();
    l.leafBrushCount = r.i32();
    return l;
  });
  bsp.leafFaces = reader.records<int32_t>(L[q3::LeafSurfaces], 4, [](FieldReader& r) { return r.i32(); });
  bsp.leafBrushes = reader.records<int32_t>(L[q3::LeafBrushes], 4, [](FieldReader& r) { return r.i32(); });
  bsp.models = reader.records<Model>(L[q3::Models], 40, [](FieldReader& r) {
    Model m;
    m.mins = r.vec3();
    m.maxs = r.vec3();
    m.firstFace = r.i32();
    m.faceCount = r.i32();
    m.firstBrush = r.i32();
    m.brushCount = r.i32();
    return m;
  });
  bsp.brushes = reader.records<Brush>(L[q3::Brushes], 12, [](FieldReader& r) {
    Brush b;
    b.firstSide = r.i32();
    b.sideCount = r.i32();
    b.shader = r.i32();
    return b;
  });
  bsp.brushSides = reader.records<BrushSide>(L[q3::BrushSides], 8, [](FieldReader& r) {
    BrushSide s;
    s.plane = r.i32();
    s.shader = r.i32();
    return s;
  });
}

// The lumps from draw vertices to visibility, in the file's order.
void readQuake3DrawVertsToVisibility(const Reader& reader, std::span<const Lump> L, BspFile& bsp) {
  bsp.drawVertices = reader.records<DrawVertex>(L[q3::DrawVerts], 44, [](FieldReader& r) {
    DrawVertex v;
    v.position = r.vec3();
    v.st.x = r.f32();
    v.st.y = r.f32();
    v.lightmap.x = r.f32();
    v.lightmap.y = r.f32();
    v.normal = r.vec3();
    for (auto& c : v.color) c = r.u8();
    return v;
  });
  bsp.drawIndices = reader.records<int32_t>(L[q3::DrawIndexes], 4, [](FieldReader& r) { return r.i32(); });
  bsp.surfaces = reader.records<Surface>(L[q3::Surfaces], 104, [](FieldReader& r) {
    Surface s;
    s.shader = r.i32();
    s.fog = r.i32();
    s.type = static_cast<SurfaceType>(r.i32());
    s.firstVertex = r.i32();
    s.vertexCount = r.i32();
    s.firstIndex = r.i32();
    s.indexCount = r.i32();
    s.lightmap = r.i32();
    s.lightmapCorner = {r.i32(), r.i32()};
    s.lightmapSize = {r.i32(), r.i32()};
    s.lightmapOrigin = r.vec3();
    for (auto& v : s.lightmapVecs) v = r.vec3();
    s.patchSize = {r.i32(), r.i32()};
    return s;
  });
  bsp.lightmaps = copyBytes(L[q3::Lightmaps]);
  bsp.visibility = copyBytes(L[q3::Visibility]);
}

void checkQuake3Tree(const Reader& reader, std::span<const Lump> L, const BspFile& bsp) {
  checkNodes(reader, L[q3::Nodes], bsp, false);
  checkLeafRuns(reader, L[q3::Leafs], bsp, "leafsurfaces");
  for (size_t i = 0; i < bsp.leafFaces.size(); ++i)
    reader.checkIndex(L[q3::LeafSurfaces], i, "surface", bsp.leafFaces[i], bsp.surfaces.size());
  for (size_t i = 0; i < bsp.leafBrushes.size(); ++i)
    reader.checkIndex(L[q3::LeafBrushes], i, "brush", bsp.leafBrushes[i], bsp.brushes.size());
  for (size_t i = 0; i < bsp.models.size(); ++i) {
    const Model& m = bsp.models[i];
    reader.checkRange(L[q3::Models], i, "surfaces", m.firstFace, m.faceCount, bsp.surfaces.size());
    reader.checkRange(L[q3::Models], i, "brushes", m.firstBrush, m.brushCount, bsp.brushes.size());
  }
  for (size_t i = 0; i < bsp.brushes.size(); ++i) {
    const Brush& b = bsp.brushes[i];
    reader.checkRange(L[q3::Brushes], i, "brushsides", b.firstSide, b.sideCount, bsp.brushSides.size());
    checkBrushSideCount(reader, L[q3::Brushes], i, b.sideCount);
    reader.checkIndex(L[q3::Brushes], i, "shader", b.shader, bsp.shaders.size());
  }
  for (size_t i = 0; i < bsp.brushSides.size(); ++i) {
    reader.checkIndex(L[q3::BrushSides], i, "plane", bsp.brushSides[i].plane, bsp.planes.size());
    reader.checkIndex(L[q3::BrushSides], i, "shader", bsp.brushSides[i].shader, bsp.shaders.size());
  }
}

void checkQuake3Surfaces(const Reader& reader, std::span<const Lump> L, const BspFile& bsp) {
  // q3map2 gives every surface vertices of its own but lets surfaces share one index list, so
  // indexes alone do not bound the triangles. Their vertices do: a plane triangulation of V
  // points has at most 2V triangles (6V indexes), a closed mesh with g handles 2V - 4 + 4g (a
  // model of a grating: at most about 3V, 9V indexes). OpenArena's levels stay under 5.5 indexes a
  // vertex; the limit, 24, leaves models room while keeping the triangles linear in the file.
  // Without both checks, surfaces naming one long run would multiply its triangles.
  constexpr int64_t kMaxIndexesPerVertex = 24;
  uint64_t surfaceVertices = 0;
  for (size_t i = 0; i < bsp.surfaces.size(); ++i) {
    const Surface& s = bsp.surfaces[i];
    reader.checkIndex(L[q3::Surfaces], i, "shader", s.shader, bsp.shaders.size());
    reader.checkRange(L[q3::Surfaces], i, "drawverts", s.firstVertex, s.vertexCount, bsp.drawVertices.size());
    reader.checkRange(L[q3::Surfaces], i, "drawindexes", s.firstIndex, s.indexCount, bsp.drawIndices.size());
    surfaceVertices += static_cast<uint64_t>(s.vertexCount);
    if (surfaceVertices > bsp.drawVertices.size())
      reader.fail(L[q3::Surfaces],
                  fmt::format("record {}: the surfaces share drawverts (their runs add up to more than the {} "
                              "drawverts)",
                              i, bsp.drawVertices.size()));
    if (int64_t{s.indexCount} > kMaxIndexesPerVertex * int64_t{s.vertexCount})
      reader.fail(L[q3::Surfaces],
                  fmt::format("record {}: {} indexes for {} vertices (more than {} a vertex: no mesh of V "
                              "vertices has that many triangles)",
                              i, s.indexCount, s.vertexCount, kMaxIndexesPerVertex));
    for (int32_t k = 0; k < s.indexCount; ++k)
      reader.checkIndex(L[q3::Surfaces], i, "surface vertex", bsp.drawIndices[s.firstIndex + k], s.vertexCount);
    if (s.type == SurfaceType::Patch &&
        (s.patchSize[0] < 0 || s.patchSize[1] < 0 || int64_t{s.patchSize[0]} * s.patchSize[1] > s.vertexCount))
      reader.fail(L[q3::Surfaces],
                  fmt::format("record {}: patch {}x{} needs more than its {} vertices", i, s.patchSize[0], s.patchSize[1], s.vertexCount));
  }
}

} // namespace

void readQuake3(const Reader& reader, BspFile& bsp) {
  const auto L = reader.lumpTable(8, q3::kNames, q3::Count);
  readQuake3EntitiesToBrushSides(reader, L, bsp);
  readQuake3DrawVertsToVisibility(reader, L, bsp);
  checkQuake3Tree(reader, L, bsp);
  checkQuake3Surfaces(reader, L, bsp);
}

} // namespace bt::bsp::detail
