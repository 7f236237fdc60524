// Quake 1's BSP files and their kin: BSP29 (Quake, Hexen II), BSP2 and 2PSB (32-bit indices),
// BSP30 (Half-Life). Layouts as ericw-tools' bspfile_q1 and id's bspfile.h.
#include "importers/bsp/bsp_lumps.h"

#include <algorithm>

namespace bt::bsp::detail {

namespace {

// The lump numbers. Quake 1 and Half-Life share one table.
namespace q1 {
enum : int {
  Entities,
  Planes,
  Textures,
  Vertices,
  Visibility,
  Nodes,
  Texinfo,
  Faces,
  Lighting,
  ClipNodes,
  Leafs,
  MarkSurfaces,
  Edges,
  SurfEdges,
  Models,
  Count
};
constexpr const char* kNames[Count] = {"entities", "planes",    "textures", "vertexes",     "visibility", "nodes",     "texinfo", "faces",
                                       "lighting", "clipnodes", "leafs",    "marksurfaces", "edges",      "surfedges", "models"};
} // namespace q1

// Record sizes that differ between the 16-bit and the two 32-bit layouts.
struct Q1Layout {
  bool wide;        // BSP2 or 2PSB: 32-bit indices
  bool floatBounds; // BSP2: float node/leaf bounds (2PSB keeps int16)
  size_t nodeSize() const { return !wide ? 24 : floatBounds ? 44 : 32; }
  size_t leafSize() const { return !wide ? 28 : floatBounds ? 44 : 32; }
  size_t faceSize() const { return wide ? 28 : 20; }
  size_t clipNodeSize() const { return wide ? 12 : 8; }
  size_t edgeSize() const { return wide ? 8 : 4; }
  size_t markSurfaceSize() const { return wide ? 4 : 2; }
  size_t boundsSize() const { return floatBounds ? 24 : 12; }
};

std::vector<Miptex> readMiptexLump(const Reader& reader, const Lump& lump) {
  std::vector<Miptex> out;
  if (lump.bytes.empty()) return out;
  if (lump.bytes.size() < 4) reader.fail(lump, "too short for the texture count");
  FieldReader header(lump.bytes);
  const int64_t count = header.i32();
  if (count < 0 || 4 + count * 4 > static_cast<int64_t>(lump.bytes.size()))
    reader.fail(lump, fmt::format("texture count {} does not fit in {} bytes", count, lump.bytes.size()));
  std::vector<int64_t> offsets(static_cast<size_t>(count));
  for (auto& o : offsets) o = header.i32();

  // Each record runs to the next record's start (or the lump's end): sorted starts give that.
  std::vector<int64_t> starts;
  for (int64_t o : offsets)
    if (o >= 0) starts.push_back(o);
  std::sort(starts.begin(), starts.end());

  constexpr int64_t kHeaderSize = 16 + 4 + 4 + 4 * 4; // name, width, height, 4 mip offsets
  // Records that do not overlap add up to at most the lump; slots sharing one record would copy
  // it again each time (a 64 KB lump of slots all at one offset: a GB of copies).
  int64_t copied = 0;
  for (size_t i = 0; i < offsets.size(); ++i) {
    Miptex mip;
    const int64_t offset = offsets[i];
    if (offset == -1) { // slot left empty by the compiler
      out.push_back(std::move(mip));
      continue;
    }
    if (offset < 0 || offset + kHeaderSize > static_cast<int64_t>(lump.bytes.size()))
      reader.fail(lump, fmt::format("texture {} at offset {} lies outside the lump ({} bytes)", i, offset, lump.bytes.size()));
    auto next = std::upper_bound(starts.begin(), starts.end(), offset);
    // Clamped: a later entry's offset may itself be bad (it is reported when its turn comes).
    const int64_t lumpSize = static_cast<int64_t>(lump.bytes.size());
    const int64_t end = next == starts.end() ? lumpSize : std::min(*next, lumpSize);
    copied += end - offset;
    if (copied > lumpSize)
      reader.fail(lump,
                  fmt::format("texture {} at offset {} shares its record with another texture (the records add up "
                              "to more than the lump's {} bytes)",
                              i, offset, lumpSize));
    FieldReader r(lump.bytes.subspan(static_cast<size_t>(offset)));
    mip.present = true;
    mip.name = r.name(16);
    mip.width = r.u32();
    mip.height = r.u32();
    mip.hasPixels = r.u32() != 0; // mip offset 0 = no pixels here (external or -notex)
    mip.bytes.assign(lump.bytes.begin() + offset, lump.bytes.begin() + end);
    out.push_back(std::move(mip));
  }
  return out;
}

// Hexen II's models carry 8 hull head nodes instead of 4 (80 bytes instead of 64) under the same
// version number. Decide by the lump length and, when both divide it, by which reading gives the
// face ranges qbsp writes (model 0 starts at face 0, each model follows the previous one).
bool looksLikeHexen2Models(const Lump& lump) {
  const size_t size = lump.bytes.size();
  const bool q1 = size % 64 == 0, h2 = size % 80 == 0;
  if (q1 != h2) return h2;
  if (!q1) return false; // neither: let the record reader report it
  auto contiguous = [&](size_t recordSize, size_t faceFieldOffset) {
    int64_t expected = 0;
    for (size_t i = 0; i < size / recordSize; ++i) {
      FieldReader r(lump.bytes.subspan(i * recordSize + faceFieldOffset, 8));
      const int64_t first = r.i32(), count = r.i32();
      if (first != expected || count < 0) return false;
      expected = first + count;
    }
    return true;
  };
  return !contiguous(64, 56) && contiguous(80, 72);
}

// The lumps from planes to lighting, in the file's order (so that of two bad lumps the first is
// the one reported).
void readQuake1PlanesToLighting(const Reader& reader, std::span<const Lump> L, const Q1Layout& layout, BspFile& bsp) {
  bsp.entities = entitiesText(L[q1::Entities]);
  bsp.planes = reader.records<BspPlane>(L[q1::Planes], 20, [](FieldReader& r) {
    BspPlane p;
    p.normal = r.vec3();
    p.dist = r.f32();
    p.type = r.i32();
    return p;
  });
  bsp.miptex = readMiptexLump(reader, L[q1::Textures]);
  bsp.vertices = reader.records<glm::vec3>(L[q1::Vertices], 12, [](FieldReader& r) { return r.vec3(); });
  bsp.visibility = copyBytes(L[q1::Visibility]);
  bsp.nodes = reader.records<Node>(L[q1::Nodes], layout.nodeSize(), [&](FieldReader& r) {
    Node n;
    n.plane = r.i32();
    if (layout.wide) {
      n.children = {r.i32(), r.i32()};
    } else {
      n.children = {r.i16(), r.i16()};
    }
    r.skip(layout.boundsSize());
    n.firstFace = layout.wide ? r.i32() : r.u16();
    n.faceCount = layout.wide ? r.i32() : r.u16();
    return n;
  });
  bsp.texinfo = reader.records<TexInfo>(L[q1::Texinfo], 40, [](FieldReader& r) {
    TexInfo t;
    for (auto& v : t.vecs)
      for (float& f : v) f = r.f32();
    t.miptex = r.i32();
    t.flags = r.i32();
    return t;
  });
  bsp.faces = reader.records<Face>(L[q1::Faces], layout.faceSize(), [&](FieldReader& r) {
    Face f;
    if (layout.wide) {
      f.plane = r.i32();
      f.side = r.i32();
      f.firstEdge = r.i32();
      f.edgeCount = r.i32();
      f.texinfo = r.i32();
    } else {
      f.plane = r.u16();
      f.side = r.i16();
      f.firstEdge = r.i32();
      f.edgeCount = r.u16();
      f.texinfo = r.u16();
    }
    for (auto& s : f.styles) s = r.u8();
    f.lightOffset = r.i32();
    return f;
  });
  bsp.lighting = copyBytes(L[q1::Lighting]);
}

// The lumps from clip nodes to surfedges, in the file's order.
void readQuake1ClipNodesToSurfEdges(const Reader& reader, std::span<const Lump> L, const Q1Layout& layout, BspFile& bsp) {
  bsp.clipNodes = reader.records<ClipNode>(L[q1::ClipNodes], layout.clipNodeSize(), [&](FieldReader& r) {
    ClipNode c;
    c.plane = r.i32();
    if (layout.wide) {
      c.children = {r.i32(), r.i32()};
    } else {
      c.children = {r.i16(), r.i16()};
    }
    return c;
  });
  bsp.leafs = reader.records<Leaf>(L[q1::Leafs], layout.leafSize(), [&](FieldReader& r) {
    Leaf l;
    l.contents = r.i32();
    l.cluster = r.i32(); // visofs
    r.skip(layout.boundsSize());
    l.firstLeafFace = layout.wide ? r.i32() : r.u16();
    l.leafFaceCount = layout.wide ? r.i32() : r.u16();
    return l;
  });
  bsp.leafFaces = reader.records<int32_t>(L[q1::MarkSurfaces], layout.markSurfaceSize(),
                                          [&](FieldReader& r) { return layout.wide ? r.i32() : int32_t{r.u16()}; });
  bsp.edges = reader.records<std::array<uint32_t, 2>>(L[q1::Edges], layout.edgeSize(), [&](FieldReader& r) {
    if (layout.wide) return std::array<uint32_t, 2>{r.u32(), r.u32()};
    return std::array<uint32_t, 2>{r.u16(), r.u16()};
  });
  bsp.surfedges = reader.records<int32_t>(L[q1::SurfEdges], 4, [](FieldReader& r) { return r.i32(); });
}

// Models: Quake's 4 hull head nodes, or Hexen II's 8.
void readQuake1Models(const Reader& reader, std::span<const Lump> L, BspFile& bsp) {
  bsp.hexen2Models = bsp.version == Version::Bsp29 && looksLikeHexen2Models(L[q1::Models]);
  const int hulls = bsp.hexen2Models ? 8 : 4;
  bsp.models = reader.records<Model>(L[q1::Models], bsp.hexen2Models ? 80 : 64, [&](FieldReader& r) {
    Model m;
    m.mins = r.vec3();
    m.maxs = r.vec3();
    m.origin = r.vec3();
    for (int h = 0; h < hulls; ++h) m.headNode[h] = r.i32();
    m.visLeafs = r.i32();
    m.firstFace = r.i32();
    m.faceCount = r.i32();
    return m;
  });
}

void checkQuake1(const Reader& reader, std::span<const Lump> L, BspFile& bsp) {
  // Names for texinfo, now that the miptex table is known.
  for (size_t i = 0; i < bsp.texinfo.size(); ++i) {
    TexInfo& t = bsp.texinfo[i];
    reader.checkIndex(L[q1::Texinfo], i, "texture", t.miptex, bsp.miptex.size());
    t.texture = bsp.miptex[t.miptex].name;
  }
  checkNodes(reader, L[q1::Nodes], bsp, true);
  for (size_t i = 0; i < bsp.clipNodes.size(); ++i) {
    const ClipNode& c = bsp.clipNodes[i];
    reader.checkIndex(L[q1::ClipNodes], i, "plane", c.plane, bsp.planes.size());
    for (int32_t child : c.children)
      if (child >= 0) reader.checkIndex(L[q1::ClipNodes], i, "clipnode", child, bsp.clipNodes.size());
  }
  for (size_t i = 0; i < bsp.leafs.size(); ++i)
    reader.checkRange(L[q1::Leafs], i, "marksurfaces", bsp.leafs[i].firstLeafFace, bsp.leafs[i].leafFaceCount, bsp.leafFaces.size());
  for (size_t i = 0; i < bsp.leafFaces.size(); ++i) reader.checkIndex(L[q1::MarkSurfaces], i, "face", bsp.leafFaces[i], bsp.faces.size());
  const int hulls = bsp.hexen2Models ? 8 : 4;
  for (size_t i = 0; i < bsp.models.size(); ++i) {
    const Model& m = bsp.models[i];
    // A model without faces (a trigger made of clip brushes) may still name node 0.
    if (!bsp.nodes.empty()) reader.checkIndex(L[q1::Models], i, "node", m.headNode[0], bsp.nodes.size());
    for (int h = 1; h < hulls; ++h)
      if (m.headNode[h] >= 0 && !bsp.clipNodes.empty())
        reader.checkIndex(L[q1::Models], i, "clipnode", m.headNode[h], bsp.clipNodes.size());
    reader.checkRange(L[q1::Models], i, "faces", m.firstFace, m.faceCount, bsp.faces.size());
  }
}

} // namespace

void readQuake1(const Reader& reader, BspFile& bsp) {
  const auto lumps = reader.lumpTable(4, q1::kNames, q1::Count);
  const Q1Layout layout{bsp.version == Version::Bsp2 || bsp.version == Version::Bsp2rmq, bsp.version == Version::Bsp2};
  readQuake1PlanesToLighting(reader, lumps, layout, bsp);
  readQuake1ClipNodesToSurfEdges(reader, lumps, layout, bsp);
  readQuake1Models(reader, lumps, bsp);
  checkQuake1(reader, lumps, bsp);
  checkFaceChain(reader, bsp);
  readBspx(reader, bsp, lumps);
}

} // namespace bt::bsp::detail
