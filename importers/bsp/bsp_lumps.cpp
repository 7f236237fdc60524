#include "importers/bsp/bsp_lumps.h"

#include <algorithm>

namespace bt::bsp::detail {

std::string entitiesText(const Lump& lump) {
  const auto* begin = reinterpret_cast<const char*>(lump.bytes.data());
  const auto* nul = static_cast<const char*>(std::memchr(begin, 0, lump.bytes.size()));
  return std::string(begin, nul ? static_cast<size_t>(nul - begin) : lump.bytes.size());
}

std::vector<uint8_t> copyBytes(const Lump& lump) {
  return {lump.bytes.begin(), lump.bytes.end()};
}

void checkNodes(const Reader& reader, const Lump& lump, const BspFile& bsp, bool nodesHaveFaces) {
  for (size_t i = 0; i < bsp.nodes.size(); ++i) {
    const Node& n = bsp.nodes[i];
    reader.checkIndex(lump, i, "plane", n.plane, bsp.planes.size());
    for (int32_t child : n.children) {
      if (child >= 0)
        reader.checkIndex(lump, i, "node", child, bsp.nodes.size());
      else
        reader.checkIndex(lump, i, "leaf", -1 - int64_t{child}, bsp.leafs.size());
    }
    if (nodesHaveFaces) reader.checkRange(lump, i, "faces", n.firstFace, n.faceCount, bsp.faces.size());
  }
}

void checkLeafRuns(const Reader& reader, const Lump& lump, const BspFile& bsp, const char* faceRuns) {
  for (size_t i = 0; i < bsp.leafs.size(); ++i) {
    const Leaf& l = bsp.leafs[i];
    reader.checkRange(lump, i, faceRuns, l.firstLeafFace, l.leafFaceCount, bsp.leafFaces.size());
    reader.checkRange(lump, i, "leafbrushes", l.firstLeafBrush, l.leafBrushCount, bsp.leafBrushes.size());
  }
}

void checkBrushSideCount(const Reader& reader, const Lump& lump, size_t record, int32_t sideCount) {
  constexpr int32_t kMaxBrushSides = 1024;
  if (sideCount > kMaxBrushSides)
    reader.fail(lump, fmt::format("record {} has {} sides, more than the {} a brush may have", record, sideCount, kMaxBrushSides));
}

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

void readBspx(const Reader& reader, BspFile& bsp, std::span<const Lump> lumps) {
  size_t end = 0;
  const auto* fileStart = reader.file().data();
  for (const Lump& l : lumps)
    if (!l.bytes.empty()) end = std::max(end, static_cast<size_t>(l.bytes.data() - fileStart) + l.bytes.size());
  end = (end + 3) & ~size_t{3};
  const auto file = reader.file();
  if (end + 8 > file.size() || std::memcmp(file.data() + end, "BSPX", 4) != 0) return;
  FieldReader header(file.subspan(end + 4));
  const int64_t count = header.i32();
  const Lump directory{"BSPX", file.subspan(end)};
  if (count < 0 || end + 8 + count * 32 > file.size()) reader.fail(directory, fmt::format("{} entries do not fit in the file", count));
  // Lumps that do not overlap add up to at most the file; overlapping ones would copy the same
  // bytes again and again (a few MB of directory naming the whole file: terabytes).
  uint64_t copied = 0;
  for (int64_t i = 0; i < count; ++i) {
    FieldReader r(file.subspan(end + 8 + i * 32, 32));
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

} // namespace bt::bsp::detail
