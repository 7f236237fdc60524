// Quake 2's BSP files: IBSP 38. Layout as id's qfiles.h and ericw-tools' bspfile_q2.
#include "importers/bsp/bsp_lumps.h"

namespace bt::bsp::detail {

namespace {

namespace q2 {
enum : int {
  Entities,
  Planes,
  Vertices,
  Visibility,
  Nodes,
  Texinfo,
  Faces,
  Lighting,
  Leafs,
  LeafFaces,
  LeafBrushes,
  Edges,
  SurfEdges,
  Models,
  Brushes,
  BrushSides,
  Pop,
  Areas,
  AreaPortals,
  Count
};
constexpr const char* kNames[Count] = {"entities", "planes",     "vertexes",  "visibility",  "nodes",      "texinfo",   "faces",
                                       "lighting", "leafs",      "leaffaces", "leafbrushes", "edges",      "surfedges", "models",
                                       "brushes",  "brushsides", "pop",       "areas",       "areaportals"};
} // namespace q2

// The lumps from entities to lighting, in the file's order (so that of two bad lumps the first
// is the one reported).
void readQuake2EntitiesToLighting(const Reader& reader, std::span<const Lump> L, BspFile& bsp) {
  bsp.entities = entitiesText(L[q2::Entities]);
  bsp.planes = reader.records<BspPlane>(L[q2::Planes], 20, [](FieldReader& r) {
    BspPlane p;
    p.normal = r.vec3();
    p.dist = r.f32();
    p.type = r.i32();
    return p;
  });
  bsp.vertices = reader.records<glm::vec3>(L[q2::Vertices], 12, [](FieldReader& r) { return r.vec3(); });
  bsp.visibility = copyBytes(L[q2::Visibility]);
  bsp.nodes = reader.records<Node>(L[q2::Nodes], 28, [](FieldReader& r) {
    Node n;
    n.plane = r.i32();
    n.children = {r.i32(), r.i32()};
    r.skip(12); // int16 bounds
    n.firstFace = r.u16();
    n.faceCount = r.u16();
    return n;
  });
  bsp.texinfo = reader.records<TexInfo>(L[q2::Texinfo], 76, [](FieldReader& r) {
    TexInfo t;
    for (auto& v : t.vecs)
      for (float& f : v) f = r.f32();
    t.flags = r.i32();
    t.value = r.i32();
    t.texture = r.name(32);
    t.nextTexinfo = r.i32();
    return t;
  });
  bsp.faces = reader.records<Face>(L[q2::Faces], 20, [](FieldReader& r) {
    Face f;
    f.plane = r.u16();
    f.side = r.i16();
    f.firstEdge = r.i32();
    f.edgeCount = r.u16();
    f.texinfo = r.i16();
    for (auto& s : f.styles) s = r.u8();
    f.lightOffset = r.i32();
    return f;
  });
  bsp.lighting = copyBytes(L[q2::Lighting]);
}

// The lumps from leafs to brush sides, in the file's order.
void readQuake2LeafsToBrushSides(const Reader& reader, std::span<const Lump> L, BspFile& bsp) {
  bsp.leafs = reader.records<Leaf>(L[q2::Leafs], 28, [](FieldReader& r) {
    Leaf l;
    l.contents = r.i32();
    l.cluster = r.i16();
    l.area = r.i16();
    r.skip(12);
    l.firstLeafFace = r.u16();
    l.leafFaceCount = r.u16();
    l.firstLeafBrush = r.u16();
    l.leafBrushCount = r.u16();
    return l;
  });
  bsp.leafFaces = reader.records<int32_t>(L[q2::LeafFaces], 2, [](FieldReader& r) { return int32_t{r.u16()}; });
  bsp.leafBrushes = reader.records<int32_t>(L[q2::LeafBrushes], 2, [](FieldReader& r) { return int32_t{r.u16()}; });
  bsp.edges = reader.records<std::array<uint32_t, 2>>(L[q2::Edges], 4, [](FieldReader& r) {
    return std::array<uint32_t, 2>{r.u16(), r.u16()};
  });
  bsp.surfedges = reader.records<int32_t>(L[q2::SurfEdges], 4, [](FieldReader& r) { return r.i32(); });
  bsp.models = reader.records<Model>(L[q2::Models], 48, [](FieldReader& r) {
    Model m;
    m.mins = r.vec3();
    m.maxs = r.vec3();
    m.origin = r.vec3();
    m.headNode[0] = r.i32();
    m.firstFace = r.i32();
    m.faceCount = r.i32();
    return m;
  });
  bsp.brushes = reader.records<Brush>(L[q2::Brushes], 12, [](FieldReader& r) {
    Brush b;
    b.firstSide = r.i32();
    b.sideCount = r.i32();
    b.contents = r.i32();
    return b;
  });
  bsp.brushSides = reader.records<BrushSide>(L[q2::BrushSides], 4, [](FieldReader& r) {
    BrushSide s;
    s.plane = r.u16();
    s.texinfo = r.i16();
    return s;
  });
}

void checkQuake2(const Reader& reader, std::span<const Lump> L, const BspFile& bsp) {
  for (size_t i = 0; i < bsp.texinfo.size(); ++i)
    if (bsp.texinfo[i].nextTexinfo != -1) reader.checkIndex(L[q2::Texinfo], i, "texinfo", bsp.texinfo[i].nextTexinfo, bsp.texinfo.size());
  checkNodes(reader, L[q2::Nodes], bsp, true);
  checkLeafRuns(reader, L[q2::Leafs], bsp, "leaffaces");
  for (size_t i = 0; i < bsp.leafFaces.size(); ++i) reader.checkIndex(L[q2::LeafFaces], i, "face", bsp.leafFaces[i], bsp.faces.size());
  for (size_t i = 0; i < bsp.leafBrushes.size(); ++i)
    reader.checkIndex(L[q2::LeafBrushes], i, "brush", bsp.leafBrushes[i], bsp.brushes.size());
  for (size_t i = 0; i < bsp.models.size(); ++i) {
    const Model& m = bsp.models[i];
    if (!bsp.nodes.empty()) reader.checkIndex(L[q2::Models], i, "node", m.headNode[0], bsp.nodes.size());
    reader.checkRange(L[q2::Models], i, "faces", m.firstFace, m.faceCount, bsp.faces.size());
  }
  for (size_t i = 0; i < bsp.brushes.size(); ++i) {
    reader.checkRange(L[q2::Brushes], i, "brushsides", bsp.brushes[i].firstSide, bsp.brushes[i].sideCount, bsp.brushSides.size());
    checkBrushSideCount(reader, L[q2::Brushes], i, bsp.brushes[i].sideCount);
  }
  for (size_t i = 0; i < bsp.brushSides.size(); ++i) {
    reader.checkIndex(L[q2::BrushSides], i, "plane", bsp.brushSides[i].plane, bsp.planes.size());
    if (bsp.brushSides[i].texinfo != -1) reader.checkIndex(L[q2::BrushSides], i, "texinfo", bsp.brushSides[i].texinfo, bsp.texinfo.size());
  }
}

} // namespace

void readQuake2(const Reader& reader, BspFile& bsp) {
  const auto L = reader.lumpTable(8, q2::kNames, q2::Count);
  readQuake2EntitiesToLighting(reader, L, bsp);
  readQuake2LeafsToBrushSides(reader, L, bsp);
  checkQuake2(reader, L, bsp);
  checkFaceChain(reader, bsp);
  readBspx(reader, bsp, L); // the Quake 2 remaster's DECOUPLED_LM
}

} // namespace bt::bsp::detail
