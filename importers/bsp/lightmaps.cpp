#include "importers/bsp/lightmaps.h"

#include "quake/binary_reader.h"
#include "quake/bspfile_q1.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <span>

namespace bt::bsp {

namespace {

constexpr int kLuxel = 16;              // texels per luxel in Quake 1/2 without BSPX LMSHIFT
constexpr int kMaxLightmapSide = 1024;  // far beyond any compiler; guards corrupt texinfo
constexpr int kMaxLmShift = 15;         // LMSHIFT values above this are corrupt (ericw-tools writes 0..8)
constexpr size_t kDecoupledRecord = 40; // uint16 width, height; int32 offset; float world_to_lm[2][4]
constexpr int kQuake3Page = 128;

// The colour data the faces index, and how many bytes one luxel takes at an offset.
struct LightData {
  std::string source;
  std::span<const uint8_t> bytes;
  int offsetScale = 1;   // lightOffset counts grey luxels: .lit and RGBLIGHTING offsets are x3
  int bytesPerLuxel = 1; // 1 grey, 3 RGB
};

LightData chooseLightData(const BspFile& bsp, const std::optional<std::vector<uint8_t>>& litFile, Diagnostics& diagnostics) {
  if (bsp.version == Version::HalfLife30 || bsp.version == Version::Quake2_38) return {"RGB lighting lump", bsp.lighting, 1, 3};
  if (litFile) {
    const auto& lit = *litFile;
    const bool header =
        lit.size() >= 8 && std::memcmp(lit.data(), "QLIT", 4) == 0 && lit[4] == 1 && lit[5] == 0 && lit[6] == 0 && lit[7] == 0;
    if (header && lit.size() - 8 == bsp.lighting.size() * 3) return {".lit file", std::span(lit).subspan(8), 3, 3};
    diagnostics.push_back({Severity::Warning, bsp.path, 0, 0,
                           fmt::format(".lit file ignored: expected \"QLIT\" version 1 and {} bytes of colour, found "
                                       "{} bytes",
                                       bsp.lighting.size() * 3, lit.size())});
  }
  if (const BspxLump* rgb = bsp.findBspx("RGBLIGHTING"); rgb && rgb->bytes.size() == bsp.lighting.size() * 3)
    return {"BSPX RGBLIGHTING", rgb->bytes, 3, 3};
  return {"lighting lump", bsp.lighting, 1, 1};
}

// Where one face's luxels lie and where its samples start.
struct LuxelGrid {
  int width = 0, height = 0; // 0: no lightmap
  std::array<int, 2> mins{0, 0};
  int luxelSize = kLuxel;    // 0 for DECOUPLED_LM
  glm::dvec3 s{0.0}, t{0.0}; // model space -> luxel coordinates
  double sOffset = 0.0, tOffset = 0.0;
  bool badRecord = false; // the BSPX record itself is unusable (counted in a warning)
};

// The luxel layout of a level: Quake's fixed grid, or what the BSPX LMSHIFT / DECOUPLED_LM lumps
// say per face. A lump whose size does not match the face count is ignored with a warning.
class LuxelLayout {
public:
  LuxelLayout(const BspFile& bsp, Diagnostics& diagnostics) : bsp_(bsp) {
    const size_t faces = bsp.faces.size();
    if (const BspxLump* lump = bsp.findBspx("DECOUPLED_LM")) {
      if (lump->bytes.size() == faces * kDecoupledRecord)
        decoupled_ = &lump->bytes;
      else
        ignored(*lump, faces * kDecoupledRecord, bsp.path, diagnostics);
    }
    if (const BspxLump* lump = bsp.findBspx("LMSHIFT")) {
      if (lump->bytes.size() == faces)
        shifts_ = &lump->bytes;
      else
        ignored(*lump, faces, bsp.path, diagnostics);
    }
  }

  // The BSPX lump the per-face records come from ("" for Quake's fixed grid).
  std::string_view lumpName() const { return decoupled_ ? "DECOUPLED_LM" : shifts_ ? "LMSHIFT" : ""; }
  std::string name() const {
    return decoupled_ ? "decoupled (BSPX DECOUPLED_LM)" : shifts_ ? "per-face luxel size (BSPX LMSHIFT)" : "16 texels per luxel";
  }

  // The grid of `face` and the offset of its samples, in the units of Face::lightOffset (-1: none).
  LuxelGrid grid(size_t face, int64_t& offset) const {
    offset = bsp_.faces[face].lightOffset;
    if (decoupled_) return decoupledGrid(face, offset);
    LuxelGrid g;
    if (shifts_) {
      const int shift = (*shifts_)[face];
      if (shift > kMaxLmShift) {
        g.badRecord = true;
        return g;
      }
      g.luxelSize = 1 << shift;
    }
    const LightmapExtents e = lightmapExtents(bsp_, face, g.luxelSize);
    g.width = e.width;
    g.height = e.height;
    g.mins = e.mins;
    const TexInfo& texinfo = bsp_.texinfo[static_cast<size_t>(bsp_.faces[face].texinfo)];
    const double scale = 1.0 / g.luxelSize;
    g.s = glm::dvec3(texinfo.vecs[0][0], texinfo.vecs[0][1], texinfo.vecs[0][2]) * scale;
    g.t = glm::dvec3(texinfo.vecs[1][0], texinfo.vecs[1][1], texinfo.vecs[1][2]) * scale;
    g.sOffset = texinfo.vecs[0][3] * scale - e.mins[0];
    g.tOffset = texinfo.vecs[1][3] * scale - e.mins[1];
    return g;
  }

private:
  // ericw-tools' bspx_decoupled_lm_perface: the lightmap's size in luxels, its offset in the
  // lighting data, and two rows of a world -> luxel matrix (luxel (x, y) centred at (x, y)).
  LuxelGrid decoupledGrid(size_t face, int64_t& offset) const {
    const std::span<const uint8_t> records(*decoupled_);
    quake::LittleEndianReader record(records.subspan(face * kDecoupledRecord, kDecoupledRecord));
    const uint16_t width = record.u16(), height = record.u16();
    LuxelGrid g;
    g.luxelSize = 0;
    offset = record.i32();
    float m[8];
    for (float& v : m) v = record.f32();
    if (!std::all_of(std::begin(m), std::end(m), [](float v) { return std::isfinite(v); })) {
      g.badRecord = true;
      return g;
    }
    g.width = width;
    g.height = height;
    g.s = {m[0], m[1], m[2]};
    g.sOffset = m[3];
    g.t = {m[4], m[5], m[6]};
    g.tOffset = m[7];
    return g;
  }

  static void ignored(const BspxLump& lump, size_t expected, const std::string& path, Diagnostics& diagnostics) {
    diagnostics.push_back(
        {Severity::Warning, path, 0, 0,
         fmt::format("lump 'BSPX {}' ignored: {} bytes where the faces need {}", lump.name, lump.bytes.size(), expected)});
  }

  const BspFile& bsp_;
  const std::vector<uint8_t>* decoupled_ = nullptr;
  const std::vector<uint8_t>* shifts_ = nullptr;
};

} // namespace

LightmapExtents lightmapExtents(const BspFile& bsp, size_t face, int luxelSize) {
  const Face& f = bsp.faces[face];
  const TexInfo& texinfo = bsp.texinfo[static_cast<size_t>(f.texinfo)];
  // As the light tool computes them (ericw-tools faceextents_t): texel coordinates in extended
  // precision, then stored as float. At scale 3, -144 * (1/3.f) is -48.0000001 in double, -48 in
  // float; computing in float throughout instead loses a luxel elsewhere (45-degree faces).
  float lo[2] = {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity()};
  float hi[2] = {-lo[0], -lo[1]};
  for (const glm::dvec3& p : bsp.faceVertices(face)) {
    for (int i = 0; i < 2; ++i) {
      const auto& v = texinfo.vecs[static_cast<size_t>(i)];
      const long double exact =
          static_cast<long double>(p.x) * v[0] + static_cast<long double>(p.y) * v[1] + static_cast<long double>(p.z) * v[2] + v[3];
      if (!(std::fabs(exact) < 1e9L)) return {}; // corrupt texinfo or vertices (also NaN)
      const float st = static_cast<float>(exact);
      lo[i] = std::min(lo[i], st);
      hi[i] = std::max(hi[i], st);
    }
  }
  LightmapExtents e;
  int size[2] = {0, 0};
  for (int i = 0; i < 2; ++i) {
    const double mins = std::floor(static_cast<double>(lo[i]) / luxelSize);
    const double maxs = std::ceil(static_cast<double>(hi[i]) / luxelSize);
    if (!std::isfinite(mins) || !std::isfinite(maxs) || maxs - mins >= kMaxLightmapSide) return {};
    e.mins[static_cast<size_t>(i)] = static_cast<int>(mins);
    size[i] = static_cast<int>(maxs - mins) + 1;
  }
  e.width = size[0];
  e.height = size[1];
  return e;
}

namespace {

// u = dot(p, axis) + offset through three points of a plane with known u: the gradient lies in
// the plane (a planar surface's lightmap is a projection of it, q3map2 lightmapVecs).
bool fitPlanarAxis(const std::array<glm::dvec3, 3>& p, const std::array<double, 3>& u, glm::dvec3& axis, double& offset) {
  const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
  const double a = glm::dot(e1, e1), b = glm::dot(e1, e2), c = glm::dot(e2, e2);
  const double det = a * c - b * b;
  if (!(std::abs(det) > 1e-9)) return false;
  const double d1 = u[1] - u[0], d2 = u[2] - u[0];
  const double alpha = (d1 * c - d2 * b) / det, beta = (d2 * a - d1 * b) / det;
  axis = alpha * e1 + beta * e2;
  offset = u[0] - glm::dot(axis, p[0]);
  return true;
}

// One planar draw surface with a lightmap as a LightmappedFace: its triangles, and the block of
// its page its vertices' lightmap coordinates reach, a luxel beyond on each side for the filter
// (q3map2 leaves lightmapCorner / lightmapSize 0 in some levels, so they are not trusted), with
// the luxel axes fitted to those coordinates (texel centres at integers: u = s × 128 - 0.5 - x0).
// False when the surface's records are unusable.
bool quake3Surface(const BspFile& bsp, const Surface& surface, const ModelPlacement& placement, LightmappedFace& lf) {
  const size_t pages = bsp.lightmaps.size() / (kQuake3Page * kQuake3Page * 3);
  if (surface.lightmap < 0 || size_t(surface.lightmap) >= pages) return false;
  if (surface.firstVertex < 0 || surface.vertexCount < 3 ||
      size_t(surface.firstVertex) + size_t(surface.vertexCount) > bsp.drawVertices.size() || surface.firstIndex < 0 ||
      surface.indexCount < 3 || size_t(surface.firstIndex) + size_t(surface.indexCount) > bsp.drawIndices.size())
    return false;
  std::vector<glm::dvec2> texel; // page texel coordinates, centres at integers
  glm::dvec2 lo(1e30), hi(-1e30);
  for (int32_t v = 0; v < surface.vertexCount; ++v) {
    const DrawVertex& dv = bsp.drawVertices[size_t(surface.firstVertex + v)];
    lf.polygon.push_back(glm::dvec3(dv.position) + placement.origin);
    texel.push_back(glm::dvec2(dv.lightmap) * double(kQuake3Page) - 0.5);
    lo = glm::min(lo, texel.back()), hi = glm::max(hi, texel.back());
  }
  if (!(lo.x > -2.0 && lo.y > -2.0 && hi.x < kQuake3Page + 1.0 && hi.y < kQuake3Page + 1.0)) return false; // also NaN
  const glm::ivec2 first = glm::clamp(glm::ivec2(glm::floor(lo)) - 1, 0, kQuake3Page - 1);
  const glm::ivec2 last = glm::clamp(glm::ivec2(glm::ceil(hi)) + 1, 0, kQuake3Page - 1);
  double bestArea = 0.0;
  std::array<size_t, 3> best{};
  for (int32_t i = 0; i + 2 < surface.indexCount; i += 3) {
    std::array<size_t, 3> t{};
    for (int k = 0; k < 3; ++k) t[size_t(k)] = size_t(bsp.drawIndices[size_t(surface.firstIndex + i + k)]);
    if (t[0] >= lf.polygon.size() || t[1] >= lf.polygon.size() || t[2] >= lf.polygon.size()) return false;
    for (size_t k : t) lf.triangles.push_back(uint32_t(k));
    const double area = glm::length(glm::cross(lf.polygon[t[1]] - lf.polygon[t[0]], lf.polygon[t[2]] - lf.polygon[t[0]]));
    if (area > bestArea) bestArea = area, best = t;
  }
  const std::array<glm::dvec3, 3> p{lf.polygon[best[0]], lf.polygon[best[1]], lf.polygon[best[2]]};
  // The plane's normal: lightmapVecs[2], which some q3map2 versions leave zero, else the largest
  // triangle's, turned to the side the vertex normals face.
  lf.normal = glm::dvec3(surface.lightmapVecs[2]);
  if (!(std::abs(glm::length(lf.normal) - 1.0) < 1e-3)) {
    lf.normal = glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));
    if (glm::dot(lf.normal, glm::dvec3(bsp.drawVertices[size_t(surface.firstVertex) + best[0]].normal)) < 0.0) lf.normal = -lf.normal;
    if (!(std::abs(glm::length(lf.normal) - 1.0) < 1e-3)) return false; // also NaN: no triangle with an area
  }
  const auto coordinate = [&](int axis) {
    return std::array<double, 3>{texel[best[0]][axis] - first[axis], texel[best[1]][axis] - first[axis],
                                 texel[best[2]][axis] - first[axis]};
  };
  if (!fitPlanarAxis(p, coordinate(0), lf.luxelS, lf.luxelSOffset) || !fitPlanarAxis(p, coordinate(1), lf.luxelT, lf.luxelTOffset))
    return false;
  lf.entity = placement.entity;
  lf.luxelSize = 0;
  lf.width = last.x - first.x + 1;
  lf.height = last.y - first.y + 1;
  lf.styles = {0, 255, 255, 255};
  const uint8_t* page = bsp.lightmaps.data() + size_t(surface.lightmap) * kQuake3Page * kQuake3Page * 3;
  for (int y = first.y; y <= last.y; ++y)
    for (int x = first.x; x <= last.x; ++x)
      for (int c = 0; c < 3; ++c) lf.rgb.push_back(page[(size_t(y) * kQuake3Page + size_t(x)) * 3 + size_t(c)]);
  return true;
}

// Quake 3: the 128x128 lightmap pages, and each planar surface's rectangle on its page.
void readQuake3Lighting(const BspFile& bsp, const std::vector<ModelPlacement>& placements, CompiledLighting& out,
                        Diagnostics& diagnostics) {
  out.source = "lightmap pages";
  const size_t pageBytes = kQuake3Page * kQuake3Page * 3;
  for (size_t at = 0; at + pageBytes <= bsp.lightmaps.size(); at += pageBytes) {
    Image page;
    page.width = page.height = kQuake3Page;
    page.rgba.resize(kQuake3Page * kQuake3Page * 4);
    for (size_t i = 0; i < kQuake3Page * kQuake3Page; ++i) {
      std::memcpy(&page.rgba[i * 4], &bsp.lightmaps[at + i * 3], 3);
      page.rgba[i * 4 + 3] = 255;
    }
    out.pages.push_back(std::move(page));
  }
  size_t unusable = 0;
  for (const ModelPlacement& placement : placements) {
    const Model& model = bsp.models[placement.model];
    for (int32_t i = 0; i < model.faceCount; ++i) {
      const Surface& surface = bsp.surfaces[size_t(model.firstFace + i)];
      if (surface.type != SurfaceType::Planar || surface.lightmap < 0) continue;
      LightmappedFace lf;
      if (quake3Surface(bsp, surface, placement, lf))
        out.faces.push_back(std::move(lf));
      else
        ++unusable;
    }
  }
  if (unusable > 0)
    diagnostics.push_back({Severity::Warning, bsp.path, 0, 0,
                           fmt::format("lump 'surfaces': {} planar surfaces with a lightmap point outside their page, "
                                       "vertices or indices, or lie on no plane; they are kept without a lightmap",
                                       unusable)});
}

// A Quake 1/2 face where the placement puts it: polygon, normal, texture and its axes.
LightmappedFace placedFace(const BspFile& bsp, size_t f, const ModelPlacement& placement) {
  const Face& face = bsp.faces[f];
  const TexInfo& texinfo = bsp.texinfo[static_cast<size_t>(face.texinfo)];
  const BspPlane& plane = bsp.planes[static_cast<size_t>(face.plane)];
  LightmappedFace lf;
  lf.entity = placement.entity;
  const auto points = bsp.faceVertices(f);
  for (auto it = points.rbegin(); it != points.rend(); ++it) lf.polygon.push_back(*it + placement.origin);
  lf.normal = glm::dvec3(plane.normal) * (face.side ? -1.0 : 1.0);
  lf.texture = texinfo.texture;
  lf.sAxis = {texinfo.vecs[0][0], texinfo.vecs[0][1], texinfo.vecs[0][2]};
  lf.tAxis = {texinfo.vecs[1][0], texinfo.vecs[1][1], texinfo.vecs[1][2]};
  // Moving the face by the origin moves its texture and its luxels with it.
  lf.sOffset = texinfo.vecs[0][3] - glm::dot(lf.sAxis, placement.origin);
  lf.tOffset = texinfo.vecs[1][3] - glm::dot(lf.tAxis, placement.origin);
  return lf;
}

// The face's luxels of every style, as RGB; false when the face points past the light data.
bool copyLuxels(const Face& face, const LuxelGrid& grid, int64_t offset, const LightData& data, LightmappedFace& lf) {
  const int styleCount = static_cast<int>(std::count_if(face.styles.begin(), face.styles.end(), [](uint8_t s) { return s != 255; }));
  if (offset < 0 || styleCount == 0 || grid.width <= 0 || grid.height <= 0) return true;
  // 64-bit sizes: a corrupt DECOUPLED_LM record may claim 65535 x 65535 luxels.
  const size_t luxels = static_cast<size_t>(grid.width) * static_cast<size_t>(grid.height);
  const size_t begin = static_cast<size_t>(offset) * static_cast<size_t>(data.offsetScale);
  const size_t length = luxels * static_cast<size_t>(styleCount) * static_cast<size_t>(data.bytesPerLuxel);
  if (begin > data.bytes.size() || data.bytes.size() - begin < length) return false;
  lf.lightmapMins = grid.mins;
  lf.width = grid.width;
  lf.height = grid.height;
  lf.styles = face.styles;
  const uint8_t* src = data.bytes.data() + begin;
  lf.rgb.resize(luxels * static_cast<size_t>(styleCount) * 3);
  for (size_t k = 0; k < luxels * static_cast<size_t>(styleCount); ++k)
    for (int c = 0; c < 3; ++c) lf.rgb[k * 3 + static_cast<size_t>(c)] = src[data.bytesPerLuxel == 3 ? k * 3 + c : k];
  return true;
}

// Quake 1 / Half-Life: which faces ericw-tools `light` spreads `_surface` points over
// (LightmappedFace::takesSurfaceLights; light's MakeSurfaceLights): those some leaf lists, a
// liquid's face ('*', Half-Life's '!') only where a leaf not in liquid (nor solid) lists it.
std::vector<bool> surfaceLightFaces(const BspFile& bsp) {
  std::vector<bool> takes(bsp.faces.size(), false);
  for (const Leaf& leaf : bsp.leafs) {
    const bool underwater = leaf.contents != quake::q1::CONTENTS_EMPTY;
    for (int32_t k = 0; k < leaf.leafFaceCount; ++k) {
      const int64_t listed = int64_t(leaf.firstLeafFace) + k;
      if (listed < 0 || size_t(listed) >= bsp.leafFaces.size()) break;
      const int32_t f = bsp.leafFaces[size_t(listed)];
      if (f < 0 || size_t(f) >= bsp.faces.size()) continue;
      const std::string& texture = bsp.texinfo[size_t(bsp.faces[size_t(f)].texinfo)].texture;
      const bool liquid = !texture.empty() && (texture[0] == '*' || texture[0] == '!');
      if (underwater && liquid) continue;
      takes[size_t(f)] = true;
    }
  }
  return takes;
}

// Quake 1/2 and Half-Life: each face's luxel grid and its bytes in the chosen light data.
void readFaceLighting(const BspFile& bsp, const std::vector<ModelPlacement>& placements, const std::optional<std::vector<uint8_t>>& litFile,
                      CompiledLighting& out, Diagnostics& diagnostics) {
  const LightData data = chooseLightData(bsp, litFile, diagnostics);
  const LuxelLayout layout(bsp, diagnostics);
  out.source = data.source;
  out.layout = layout.name();
  out.luxelSize = kLuxel;
  size_t outOfBounds = 0, badRecords = 0;
  const std::vector<bool> takesSurfaceLights = bsp.version == Version::Quake2_38 ? std::vector<bool>() : surfaceLightFaces(bsp);
  for (const ModelPlacement& placement : placements) {
    const Model& model = bsp.models[placement.model];
    for (int32_t i = 0; i < model.faceCount; ++i) {
      const size_t f = static_cast<size_t>(model.firstFace + i);
      LightmappedFace lf = placedFace(bsp, f, placement);
      lf.takesSurfaceLights = f < takesSurfaceLights.size() && takesSurfaceLights[f];
      int64_t offset = -1;
      const LuxelGrid grid = layout.grid(f, offset);
      badRecords += grid.badRecord;
      lf.luxelSize = grid.luxelSize;
      lf.luxelS = grid.s;
      lf.luxelT = grid.t;
      lf.luxelSOffset = grid.sOffset - glm::dot(grid.s, placement.origin);
      lf.luxelTOffset = grid.tOffset - glm::dot(grid.t, placement.origin);
      if (!copyLuxels(bsp.faces[f], grid, offset, data, lf)) ++outOfBounds;
      out.faces.push_back(std::move(lf));
    }
  }
  if (outOfBounds > 0)
    diagnostics.push_back({Severity::Warning, bsp.path, 0, 0,
                           fmt::format("lump 'lighting': {} faces point past the end of the {} ({} bytes); they are "
                                       "kept without a lightmap",
                                       outOfBounds, data.source, data.bytes.size())});
  if (badRecords > 0)
    diagnostics.push_back({Severity::Warning, bsp.path, 0, 0,
                           fmt::format("lump 'BSPX {}': {} faces have an unusable record (a luxel size beyond "
                                       "1 << {}, or a projection that is not finite); they are kept without a lightmap",
                                       layout.lumpName(), badRecords, kMaxLmShift)});
}

} // namespace

CompiledLighting readCompiledLighting(const BspFile& bsp, const std::vector<ModelPlacement>& placements,
                                      const std::optional<std::vector<uint8_t>>& litFile, Diagnostics& diagnostics) {
  CompiledLighting out;
  out.engine = bsp.version == Version::Quake3_46 ? "quake3"
      : bsp.version == Version::HalfLife30       ? "halflife"
      : bsp.version == Version::Quake2_38        ? "quake2"
      : bsp.hexen2Models                         ? "hexen2"
                                                 : "quake";
  if (bsp.version == Version::Quake3_46)
    readQuake3Lighting(bsp, placements, out, diagnostics);
  else
    readFaceLighting(bsp, placements, litFile, out, diagnostics);
  return out;
}

} // namespace bt::bsp
