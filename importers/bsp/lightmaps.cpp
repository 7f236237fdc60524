#include "importers/bsp/lightmaps.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace bt::bsp {

namespace {

constexpr int kLuxel = 16;            // texels per luxel in Quake 1/2 (no BSPX LMSHIFT support)
constexpr int kMaxLightmapSide = 1024; // far beyond any compiler; guards corrupt texinfo
constexpr int kQuake3Page = 128;

// The colour data the faces index, and how many bytes one luxel takes at an offset.
struct LightData {
  std::string source;
  std::span<const uint8_t> bytes;
  int offsetScale = 1;   // lightOffset counts grey luxels: .lit and RGBLIGHTING offsets are x3
  int bytesPerLuxel = 1; // 1 grey, 3 RGB
};

LightData chooseLightData(const BspFile& bsp, const std::optional<std::vector<uint8_t>>& litFile,
                          Diagnostics& diagnostics) {
  if (bsp.version == Version::HalfLife30 || bsp.version == Version::Quake2_38)
    return {"RGB lighting lump", bsp.lighting, 1, 3};
  if (litFile) {
    const auto& lit = *litFile;
    const bool header = lit.size() >= 8 && std::memcmp(lit.data(), "QLIT", 4) == 0 && lit[4] == 1 && lit[5] == 0 &&
                        lit[6] == 0 && lit[7] == 0;
    if (header && lit.size() - 8 == bsp.lighting.size() * 3)
      return {".lit file", std::span(lit).subspan(8), 3, 3};
    diagnostics.push_back({Severity::Warning, bsp.path, 0, 0,
                           fmt::format(".lit file ignored: expected \"QLIT\" version 1 and {} bytes of colour, found "
                                       "{} bytes",
                                       bsp.lighting.size() * 3, lit.size())});
  }
  if (const BspxLump* rgb = bsp.findBspx("RGBLIGHTING"); rgb && rgb->bytes.size() == bsp.lighting.size() * 3)
    return {"BSPX RGBLIGHTING", rgb->bytes, 3, 3};
  return {"lighting lump", bsp.lighting, 1, 1};
}

} // namespace

LightmapExtents lightmapExtents(const BspFile& bsp, size_t face) {
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
      const long double exact = static_cast<long double>(p.x) * v[0] + static_cast<long double>(p.y) * v[1] +
                                static_cast<long double>(p.z) * v[2] + v[3];
      if (!(std::fabs(exact) < 1e9L)) return {}; // corrupt texinfo or vertices (also NaN)
      const float st = static_cast<float>(exact);
      lo[i] = std::min(lo[i], st);
      hi[i] = std::max(hi[i], st);
    }
  }
  LightmapExtents e;
  int size[2] = {0, 0};
  for (int i = 0; i < 2; ++i) {
    const double mins = std::floor(static_cast<double>(lo[i]) / kLuxel);
    const double maxs = std::ceil(static_cast<double>(hi[i]) / kLuxel);
    if (!std::isfinite(mins) || !std::isfinite(maxs) || maxs - mins >= kMaxLightmapSide) return {};
    e.mins[static_cast<size_t>(i)] = static_cast<int>(mins);
    size[i] = static_cast<int>(maxs - mins) + 1;
  }
  e.width = size[0];
  e.height = size[1];
  return e;
}

CompiledLighting readCompiledLighting(const BspFile& bsp, const std::vector<ModelPlacement>& placements,
                                      const std::optional<std::vector<uint8_t>>& litFile, Diagnostics& diagnostics) {
  CompiledLighting out;
  if (bsp.version == Version::Quake3_46) {
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
    return out;
  }

  const LightData data = chooseLightData(bsp, litFile, diagnostics);
  out.source = data.source;
  out.luxelSize = kLuxel;
  size_t outOfBounds = 0;
  for (const ModelPlacement& placement : placements) {
    const Model& model = bsp.models[placement.model];
    for (int32_t i = 0; i < model.faceCount; ++i) {
      const size_t f = static_cast<size_t>(model.firstFace + i);
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
      // Moving the face by the origin moves its texture with it.
      lf.sOffset = texinfo.vecs[0][3] - glm::dot(lf.sAxis, placement.origin);
      lf.tOffset = texinfo.vecs[1][3] - glm::dot(lf.tAxis, placement.origin);

      const int styleCount = static_cast<int>(std::count_if(face.styles.begin(), face.styles.end(),
                                                            [](uint8_t s) { return s != 255; }));
      const LightmapExtents extents = lightmapExtents(bsp, f);
      if (face.lightOffset >= 0 && styleCount > 0 && extents.width > 0) {
        const size_t luxels = static_cast<size_t>(extents.width) * static_cast<size_t>(extents.height);
        const size_t begin = static_cast<size_t>(face.lightOffset) * static_cast<size_t>(data.offsetScale);
        const size_t length = luxels * static_cast<size_t>(styleCount) * static_cast<size_t>(data.bytesPerLuxel);
        if (begin > data.bytes.size() || data.bytes.size() - begin < length) {
          ++outOfBounds;
        } else {
          lf.lightmapMins = extents.mins;
          lf.width = extents.width;
          lf.height = extents.height;
          lf.styles = face.styles;
          const uint8_t* src = data.bytes.data() + begin;
          lf.rgb.resize(luxels * static_cast<size_t>(styleCount) * 3);
          for (size_t k = 0; k < luxels * static_cast<size_t>(styleCount); ++k)
            for (int c = 0; c < 3; ++c) lf.rgb[k * 3 + static_cast<size_t>(c)] = src[data.bytesPerLuxel == 3 ? k * 3 + c : k];
        }
      }
      out.faces.push_back(std::move(lf));
    }
  }
  if (outOfBounds > 0)
    diagnostics.push_back({Severity::Warning, bsp.path, 0, 0,
                           fmt::format("lump 'lighting': {} faces point past the end of the {} ({} bytes); they are "
                                       "kept without a lightmap",
                                       outOfBounds, data.source, data.bytes.size())});
  return out;
}

} // namespace bt::bsp
