#include "importers/bsp/bsp_file.h"

#include "importers/bsp/bsp_lumps.h"
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
  const detail::Reader reader(bytes, pathForErrors);
  BspFile bsp;
  bsp.path = pathForErrors;
  if (bytes.size() < 8) reader.fail(fmt::format("header: file is {} bytes, too short to be a BSP file", bytes.size()));

  quake::LittleEndianReader header(bytes);
  const uint32_t magic = header.u32();
  const int32_t ibspVersion = header.i32();
  auto fourCC = [](const char* s) { return quake::readU32({reinterpret_cast<const uint8_t*>(s), 4}, 0); };

  if (magic == 29 || magic == 30 || magic == fourCC("BSP2") || magic == fourCC("2PSB")) {
    bsp.version = magic == 29     ? Version::Bsp29
        : magic == 30             ? Version::HalfLife30
        : magic == fourCC("BSP2") ? Version::Bsp2
                                  : Version::Bsp2rmq;
    detail::readQuake1(reader, bsp);
  } else if (magic == fourCC("IBSP") && ibspVersion == 38) {
    bsp.version = Version::Quake2_38;
    detail::readQuake2(reader, bsp);
  } else if (magic == fourCC("IBSP") && ibspVersion == 46) {
    bsp.version = Version::Quake3_46;
    detail::readQuake3(reader, bsp);
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
