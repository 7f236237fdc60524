#include "importers/bsp/bsp_file.h"

#include "scene/diagnostics.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>

namespace bt::bsp {

const char* toString(Version version) {
  switch (version) {
  case Version::Bsp29: return "bsp29";
  case Version::Bsp2: return "bsp2";
  case Version::Bsp2rmq: return "2psb";
  case Version::HalfLife30: return "bsp30";
  case Version::Quake2_38: return "ibsp38";
  case Version::Quake3_46: return "ibsp46";
  }
  return "unknown";
}

namespace {

// Reads little-endian fields of one record, whatever the host's byte order. The caller has
// already checked that the record lies inside the lump.
class FieldReader {
public:
  explicit FieldReader(const uint8_t* p) : p_(p) {}

  uint8_t u8() { return *p_++; }
  uint16_t u16() {
    uint16_t v = static_cast<uint16_t>(p_[0] | (p_[1] << 8));
    p_ += 2;
    return v;
  }
  int16_t i16() { return static_cast<int16_t>(u16()); }
  uint32_t u32() {
    uint32_t v = static_cast<uint32_t>(p_[0]) | (static_cast<uint32_t>(p_[1]) << 8) | (static_cast<uint32_t>(p_[2]) << 16) |
        (static_cast<uint32_t>(p_[3]) << 24);
    p_ += 4;
    return v;
  }
  int32_t i32() { return static_cast<int32_t>(u32()); }
  float f32() { return std::bit_cast<float>(u32()); }
  glm::vec3 vec3() {
    float x = f32(), y = f32();
    return {x, y, f32()};
  }
  // A fixed-size, NUL-padded name field (may lack the NUL when it fills the field).
  std::string name(size_t size) {
    const auto* end = static_cast<const uint8_t*>(std::memchr(p_, 0, size));
    std::string s(reinterpret_cast<const char*>(p_), end ? static_cast<size_t>(end - p_) : size);
    p_ += size;
    return s;
  }
  void skip(size_t n) { p_ += n; }

private:
  const uint8_t* p_;
};

struct Lump {
  const char* name;
  std::span<const uint8_t> bytes;
};

// The per-version lump numbers. Quake 1 and Half-Life share one table.
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

class Reader {
public:
  Reader(std::span<const uint8_t> file, const std::string& path) : file_(file), path_(path) {}

  [[noreturn]] void fail(std::string message) const { throw ImportError(Diagnostic{Severity::Error, path_, 0, 0, std::move(message)}); }
  [[noreturn]] void fail(const Lump& lump, std::string message) const { fail(fmt::format("lump '{}': {}", lump.name, message)); }

  const std::string& path() const { return path_; }
  std::span<const uint8_t> file() const { return file_; }

  // Reads `count` lump directory entries (offset, length) starting at byte `tableOffset`.
  std::vector<Lump> lumpTable(size_t tableOffset, const char* const* names, int count) const {
    const size_t tableEnd = tableOffset + static_cast<size_t>(count) * 8;
    if (file_.size() < tableEnd)
      fail(fmt::format("header: file is {} bytes, too short for the lump table ({} bytes)", file_.size(), tableEnd));
    std::vector<Lump> lumps;
    FieldReader r(file_.data() + tableOffset);
    for (int i = 0; i < count; ++i) {
      const int64_t offset = r.i32();
      const int64_t length = r.i32();
      Lump lump{names[i], {}};
      if (offset < 0 || length < 0) fail(lump, fmt::format("negative offset {} or length {} in the lump table", offset, length));
      if (static_cast<uint64_t>(offset + length) > file_.size())
        fail(lump, fmt::format("offset {} + length {} lies past the end of the file ({} bytes)", offset, length, file_.size()));
      lump.bytes = file_.subspan(static_cast<size_t>(offset), static_cast<size_t>(length));
      lumps.push_back(lump);
    }
    return lumps;
  }

  // Splits a lump into fixed-size records and parses each with parse(FieldReader&).
  template <class Record, class Parse> std::vector<Record> records(const Lump& lump, size_t recordSize, Parse parse) const {
    if (lump.bytes.size() % recordSize != 0)
      fail(lump, fmt::format("length {} is not a multiple of the record size {}", lump.bytes.size(), recordSize));
    const size_t count = lump.bytes.size() / recordSize;
    std::vector<Record> out;
    out.reserve(count);
    for (size_t i = 0; i < count; ++i) {
      FieldReader r(lump.bytes.data() + i * recordSize);
      out.push_back(parse(r));
    }
    return out;
  }

  // Fails unless 0 <= value < count.
  void checkIndex(const Lump& lump, size_t record, const char* what, int64_t value, size_t count) const {
    if (value < 0 || static_cast<uint64_t>(value) >= count)
      fail(lump, fmt::format("record {} refers to {} {}, but there are {}", record, what, value, count));
  }
  // Fails unless [first, first + n) lies inside [0, count).
  void checkRange(const Lump& lump, size_t record, const char* what, int64_t first, int64_t n, size_t count) const {
    if (first < 0 || n < 0 || static_cast<uint64_t>(first + n) > count)
      fail(lump, fmt::format("record {} refers to {} {}..{}, but there are {}", record, what, first, first + n, count));
  }

private:
  std::span<const uint8_t> file_;
  const std::string& path_;
};

std::string entitiesText(const Lump& lump) {
  const auto* begin = reinterpret_cast<const char*>(lump.bytes.data());
  const auto* nul = static_cast<const char*>(std::memchr(begin, 0, lump.bytes.size()));
  return std::string(begin, nul ? static_cast<size_t>(nul - begin) : lump.bytes.size());
}

std::vector<uint8_t> copyBytes(const Lump& lump) {
  return {lump.bytes.begin(), lump.bytes.end()};
}

// ---------------------------------------------------------------------------------------------
// Quake 1 family: BSP29, BSP2, 2PSB, BSP30 (Half-Life)

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
  FieldReader header(lump.bytes.data());
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
    FieldReader r(lump.bytes.data() + offset);
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
      FieldReader r(lump.bytes.data() + i * recordSize + faceFieldOffset);
      const int64_t first = r.i32(), count = r.i32();
      if (first != expected || count < 0) return false;
      expected = first + count;
    }
    return true;
  };
  return !contiguous(64, 56) && contiguous(80, 72);
}

void readQuake1(const Reader& reader, BspFile& bsp) {
  const auto lumps = reader.lumpTable(4, q1::kNames, q1::Count);
  const Q1Layout layout{bsp.version == Version::Bsp2 || bsp.version == Version::Bsp2rmq, bsp.version == Version::Bsp2};
  const auto& L = lumps;

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

  // Names for texinfo, now that the miptex table is known.
  for (size_t i = 0; i < bsp.texinfo.size(); ++i) {
    TexInfo& t = bsp.texinfo[i];
    reader.checkIndex(L[q1::Texinfo], i, "texture", t.miptex, bsp.miptex.size());
    t.texture = bsp.miptex[t.miptex].name;
  }
  const Lump& nodesLump = L[q1::Nodes];
  for (size_t i = 0; i < bsp.nodes.size(); ++i) {
    const Node& n = bsp.nodes[i];
    reader.checkIndex(nodesLump, i, "plane", n.plane, bsp.planes.size());
    for (int32_t child : n.children) {
      if (child >= 0)
        reader.checkIndex(nodesLump, i, "node", child, bsp.nodes.size());
      else
        reader.checkIndex(nodesLump, i, "leaf", -1 - int64_t{child}, bsp.leafs.size());
    }
    reader.checkRange(nodesLump, i, "faces", n.firstFace, n.faceCount, bsp.faces.size());
  }
  for (size_t i = 0; i < bsp.clipNodes.size(); ++i) {
    const ClipNode& c = bsp.clipNodes[i];
    reader.checkIndex(L[q1::ClipNodes], i, "plane", c.plane, bsp.planes.size());
    for (int32_t child : c.children)
      if (child >= 0) reader.checkIndex(L[q1::ClipNodes], i, "clipnode", child, bsp.clipNodes.size());
  }
  for (size_t i = 0; i < bsp.leafs.size(); ++i)
    reader.checkRange(L[q1::Leafs], i, "marksurfaces", bsp.leafs[i].firstLeafFace, bsp.leafs[i].leafFaceCount, bsp.leafFaces.size());
  for (size_t i = 0; i < bsp.leafFaces.size(); ++i) reader.checkIndex(L[q1::MarkSurfaces], i, "face", bsp.leafFaces[i], bsp.faces.size());
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

// ericw-tools appends a directory of named extension lumps after the last standard lump,
// aligned to 4 bytes: "BSPX", int32 count, then {char name[24]; int32 offset, length} each.
void readBspx(const Reader& reader, BspFile& bsp, std::span<const Lump> lumps) {
  size_t end = 0;
  const auto* fileStart = reader.file().data();
  for (const Lump& l : lumps)
    if (!l.bytes.empty()) end = std::max(end, static_cast<size_t>(l.bytes.data() - fileStart) + l.bytes.size());
  end = (end + 3) & ~size_t{3};
  const auto file = reader.file();
  if (end + 8 > file.size() || std::memcmp(file.data() + end, "BSPX", 4) != 0) return;
  FieldReader header(file.data() + end + 4);
  const int64_t count = header.i32();
  const Lump directory{"BSPX", file.subspan(end)};
  if (count < 0 || end + 8 + count * 32 > file.size()) reader.fail(directory, fmt::format("{} entries do not fit in the file", count));
  // Lumps that do not overlap add up to at most the file; overlapping ones would copy the same
  // bytes again and again (a few MB of directory naming the whole file: terabytes).
  uint64_t copied = 0;
  for (int64_t i = 0; i < count; ++i) {
    FieldReader r(file.data() + end + 8 + i * 32);
    BspxLump lump;
    lump.name = r.name(24);
    const int64_t offset = r.i32(), length = r.i32();
    if (offset < 0 || length < 0 || static_cast<uint64_t>(offset + length) > file.size())
      reader.fail(
          fmt::format("lump 'BSPX {}': offset {} + length {} lies outside the file ({} bytes)", lump.name, offset, length, file.size()));
    copied += static_cast<uint64_t>(length);
    if (copied > file.size())
      reader.fail(
          fmt::format("lump 'BSPX {}': the BSPX lumps overlap (they add up to more than the file's {} bytes)", lump.name, file.size()));
    lump.bytes.assign(file.begin() + offset, file.begin() + offset + length);
    bsp.bspx.push_back(std::move(lump));
  }
}

// Building a brush clips each side by every other one; compilers stay far below this (qbsp3's
// MAX_BUILD_SIDES is 128), and a corrupt count must not turn into hours of clipping.
void checkBrushSideCount(const Reader& reader, const Lump& lump, size_t record, int32_t sideCount) {
  constexpr int32_t kMaxBrushSides = 1024;
  if (sideCount > kMaxBrushSides)
    reader.fail(lump, fmt::format("record {} has {} sides, more than the {} a brush may have", record, sideCount, kMaxBrushSides));
}

// ---------------------------------------------------------------------------------------------
// Quake 2: IBSP 38

void readQuake2(const Reader& reader, BspFile& bsp) {
  const auto L = reader.lumpTable(8, q2::kNames, q2::Count);

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

  for (size_t i = 0; i < bsp.texinfo.size(); ++i)
    if (bsp.texinfo[i].nextTexinfo != -1) reader.checkIndex(L[q2::Texinfo], i, "texinfo", bsp.texinfo[i].nextTexinfo, bsp.texinfo.size());
  for (size_t i = 0; i < bsp.nodes.size(); ++i) {
    const Node& n = bsp.nodes[i];
    reader.checkIndex(L[q2::Nodes], i, "plane", n.plane, bsp.planes.size());
    for (int32_t child : n.children) {
      if (child >= 0)
        reader.checkIndex(L[q2::Nodes], i, "node", child, bsp.nodes.size());
      else
        reader.checkIndex(L[q2::Nodes], i, "leaf", -1 - int64_t{child}, bsp.leafs.size());
    }
    reader.checkRange(L[q2::Nodes], i, "faces", n.firstFace, n.faceCount, bsp.faces.size());
  }
  for (size_t i = 0; i < bsp.leafs.size(); ++i) {
    const Leaf& l = bsp.leafs[i];
    reader.checkRange(L[q2::Leafs], i, "leaffaces", l.firstLeafFace, l.leafFaceCount, bsp.leafFaces.size());
    reader.checkRange(L[q2::Leafs], i, "leafbrushes", l.firstLeafBrush, l.leafBrushCount, bsp.leafBrushes.size());
  }
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

// ---------------------------------------------------------------------------------------------
// Quake 3: IBSP 46

void readQuake3(const Reader& reader, BspFile& bsp) {
  const auto L = reader.lumpTable(8, q3::kNames, q3::Count);

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

  for (size_t i = 0; i < bsp.nodes.size(); ++i) {
    const Node& n = bsp.nodes[i];
    reader.checkIndex(L[q3::Nodes], i, "plane", n.plane, bsp.planes.size());
    for (int32_t child : n.children) {
      if (child >= 0)
        reader.checkIndex(L[q3::Nodes], i, "node", child, bsp.nodes.size());
      else
        reader.checkIndex(L[q3::Nodes], i, "leaf", -1 - int64_t{child}, bsp.leafs.size());
    }
  }
  for (size_t i = 0; i < bsp.leafs.size(); ++i) {
    const Leaf& l = bsp.leafs[i];
    reader.checkRange(L[q3::Leafs], i, "leafsurfaces", l.firstLeafFace, l.leafFaceCount, bsp.leafFaces.size());
    reader.checkRange(L[q3::Leafs], i, "leafbrushes", l.firstLeafBrush, l.leafBrushCount, bsp.leafBrushes.size());
  }
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

// Checks shared by Q1 and Q2: faces → surfedges → edges → vertices, faces → planes, texinfo.
void checkFaceChain(const Reader& reader, const BspFile& bsp) {
  const Lump faces{"faces", {}}, surfedges{"surfedges", {}}, edges{"edges", {}};
  // Compilers write each face's run of surfedges after the previous face's, so the runs add up
  // to at most the lump. Faces sharing one long run would each become a polygon of it: a few
  // hundred KB of faces naming one run already cost half a GB.
  uint64_t faceEdges = 0;
  for (size_t i = 0; i < bsp.faces.size(); ++i) {
    const Face& f = bsp.faces[i];
    reader.checkIndex(faces, i, "plane", f.plane, bsp.planes.size());
    reader.checkIndex(faces, i, "texinfo", f.texinfo, bsp.texinfo.size());
    reader.checkRange(faces, i, "surfedges", f.firstEdge, f.edgeCount, bsp.surfedges.size());
    faceEdges += static_cast<uint64_t>(f.edgeCount);
    if (faceEdges > bsp.surfedges.size())
      reader.fail(faces,
                  fmt::format("record {}: the faces share surfedges (their runs add up to more than the {} "
                              "surfedges)",
                              i, bsp.surfedges.size()));
  }
  for (size_t i = 0; i < bsp.surfedges.size(); ++i) {
    const int64_t e = bsp.surfedges[i];
    reader.checkIndex(surfedges, i, "edge", e < 0 ? -e : e, bsp.edges.size());
  }
  for (size_t i = 0; i < bsp.edges.size(); ++i)
    for (uint32_t v : bsp.edges[i]) reader.checkIndex(edges, i, "vertex", v, bsp.vertices.size());
}

} // namespace

std::vector<glm::dvec3> BspFile::faceVertices(size_t face) const {
  const Face& f = faces.at(face);
  std::vector<glm::dvec3> points;
  points.reserve(static_cast<size_t>(f.edgeCount));
  for (int32_t i = 0; i < f.edgeCount; ++i) {
    const int32_t e = surfedges[static_cast<size_t>(f.firstEdge + i)];
    // A negative surfedge walks edge -e backwards, so its second vertex comes first.
    const uint32_t v = e >= 0 ? edges[static_cast<size_t>(e)][0] : edges[static_cast<size_t>(-int64_t{e})][1];
    points.emplace_back(vertices[v]);
  }
  return points;
}

std::string_view BspFile::faceTexture(size_t face) const {
  return texinfo[static_cast<size_t>(faces.at(face).texinfo)].texture;
}

const BspxLump* BspFile::findBspx(std::string_view name) const {
  for (const BspxLump& l : bspx)
    if (l.name == name) return &l;
  return nullptr;
}

BspFile readBspFile(std::span<const uint8_t> bytes, const std::string& pathForErrors) {
  Reader reader(bytes, pathForErrors);
  BspFile bsp;
  bsp.path = pathForErrors;
  if (bytes.size() < 8) reader.fail(fmt::format("header: file is {} bytes, too short to be a BSP file", bytes.size()));

  FieldReader header(bytes.data());
  const uint32_t magic = header.u32();
  const int32_t ibspVersion = header.i32();
  auto fourCC = [](const char* s) { return FieldReader(reinterpret_cast<const uint8_t*>(s)).u32(); };

  if (magic == 29 || magic == 30 || magic == fourCC("BSP2") || magic == fourCC("2PSB")) {
    bsp.version = magic == 29     ? Version::Bsp29
        : magic == 30             ? Version::HalfLife30
        : magic == fourCC("BSP2") ? Version::Bsp2
                                  : Version::Bsp2rmq;
    readQuake1(reader, bsp);
    checkFaceChain(reader, bsp);
    const auto lumps = reader.lumpTable(4, q1::kNames, q1::Count);
    readBspx(reader, bsp, lumps);
  } else if (magic == fourCC("IBSP") && ibspVersion == 38) {
    bsp.version = Version::Quake2_38;
    readQuake2(reader, bsp);
    checkFaceChain(reader, bsp);
    readBspx(reader, bsp, reader.lumpTable(8, q2::kNames, q2::Count)); // the Quake 2 remaster's DECOUPLED_LM
  } else if (magic == fourCC("IBSP") && ibspVersion == 46) {
    bsp.version = Version::Quake3_46;
    readQuake3(reader, bsp);
  } else if (magic == fourCC("IBSP") || magic == fourCC("RBSP") || magic == fourCC("VBSP")) {
    reader.fail(fmt::format("header: unsupported BSP version {} (brushtrace reads IBSP 38 and 46)", ibspVersion));
  } else {
    reader.fail(fmt::format("header: not a BSP file (starts with 0x{:08x}; expected 29, 30, BSP2, "
                            "2PSB or IBSP)",
                            magic));
  }
  return bsp;
}

BspFile readBspFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ImportError(Diagnostic{Severity::Error, path.string(), 0, 0, "cannot open file"});
  std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw ImportError(Diagnostic{Severity::Error, path.string(), 0, 0, "read error"});
  return readBspFile(bytes, path.string());
}

} // namespace bt::bsp
