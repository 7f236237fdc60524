#include "importers/map/map_writer.h"

#include "importers/map/map_geometry.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

namespace bt::map {

namespace {

bool usesValveAxes(MapDialect d) {
  return d == MapDialect::Valve220 || d == MapDialect::Quake2Valve || d == MapDialect::Quake3Valve;
}
bool hasSurfaceFields(MapDialect d) {
  return d == MapDialect::Quake2 || d == MapDialect::Quake2Valve || d == MapDialect::Quake3 || d == MapDialect::Quake3Valve ||
      d == MapDialect::Daikatana;
}

// TrenchBroom's names, so that TrenchBroom and our reader both pick the dialect up again.
const char* formatName(MapDialect d) {
  switch (d) {
  case MapDialect::Standard: return "Standard";
  case MapDialect::Valve220: return "Valve";
  case MapDialect::Quake2: return "Quake2";
  case MapDialect::Quake2Valve: return "Quake2 (Valve)";
  case MapDialect::Quake3: return "Quake3 (legacy)";
  case MapDialect::Quake3Valve: return "Quake3 (Valve)";
  case MapDialect::Hexen2: return "Hexen2";
  case MapDialect::Daikatana: return "Daikatana";
  }
  return "Standard";
}

double maxTexelError(const TexVecs& a, const TexVecs& b, const Winding& points) {
  double err = 0.0;
  for (const dvec3& p : points) err = std::max({err, std::fabs(a.s(p) - b.s(p)), std::fabs(a.t(p) - b.t(p))});
  return err;
}

class Converter {
public:
  Converter(MapDialect target, Diagnostics& report, const std::string& path) : target_(target), report_(report), path_(path) {}

  void convertBrush(MapBrush& brush) {
    if (brush.kind == MapBrush::Kind::Verbatim) return;
    const bool keepBrushDef = brush.kind == MapBrush::Kind::BrushDef && target_ == MapDialect::Quake3;
    if (brush.kind == MapBrush::Kind::BrushDef && !keepBrushDef) brush.kind = MapBrush::Kind::Brush;

    std::vector<Plane> planes;
    std::vector<size_t> faceOfPlane;
    for (size_t i = 0; i < brush.faces.size(); ++i) {
      if (auto p = planeFromPoints(brush.faces[i].points)) {
        planes.push_back(*p);
        faceOfPlane.push_back(i);
      }
    }
    const std::vector<Winding> windings = brushWindings(planes);
    for (size_t k = 0; k < planes.size(); ++k) {
      MapFace& f = brush.faces[faceOfPlane[k]];
      const Winding& w = windings[k].size() >= 3 ? windings[k] : Winding(f.points.begin(), f.points.end());
      convertFace(f, planes[k], w, keepBrushDef);
    }
    for (MapFace& f : brush.faces) convertExtras(f);
  }

private:
  void convertFace(MapFace& f, const Plane& plane, const Winding& points, bool keepBrushDef) {
    if (keepBrushDef) return;
    const TexVecs vecs = faceTextureVecs(f, plane);
    const bool quark = quarkMode(f).has_value();
    if (quark) f.trailingComment.clear(); // the projection is converted into the face's own parameters
    if (usesValveAxes(target_)) {
      if (f.tex.kind == TextureKind::Valve220) return;
      f.tex = valveFromVecs(vecs, f.tex.kind == TextureKind::Standard && !quark ? f.tex.rotation : 0.0);
      return;
    }
    if (f.tex.kind == TextureKind::Standard && !quark) return;
    const std::optional<StandardParams> fit = fitStandard(vecs, plane);
    TextureParams standard;
    standard.kind = TextureKind::Standard;
    if (fit) {
      standard.offset = fit->offset;
      standard.rotation = fit->rotation;
      standard.scale = fit->scale;
    }
    const double err = maxTexelError(vecs, textureVecs(standard, plane), points);
    if (!(err <= 0.01))
      report_.push_back(Diagnostic{Severity::Warning, path_, f.line, f.column,
                                   fmt::format("texture of '{}' cannot be represented exactly in {}: off by up to {:.3g} texels", f.texture,
                                               toString(target_), err)});
    f.tex = standard;
  }

  void convertExtras(MapFace& f) {
    if (f.surface && !hasSurfaceFields(target_)) {
      droppedField(f, "Quake 2 surface fields (contents, flags, value)");
      f.surface.reset();
    }
    if (f.hexen2Value && target_ != MapDialect::Hexen2) {
      droppedField(f, "Hexen II's extra field");
      f.hexen2Value.reset();
    }
    if (f.daikatanaColor && target_ != MapDialect::Daikatana) {
      droppedField(f, "Daikatana's surface colour");
      f.daikatanaColor.reset();
    }
  }

  void droppedField(const MapFace& f, const char* what) {
    report_.push_back(
        Diagnostic{Severity::Note, path_, f.line, f.column, fmt::format("{} dropped: {} cannot hold it", what, toString(target_))});
  }

  MapDialect target_;
  Diagnostics& report_;
  const std::string& path_;
};

void writeTexture(std::string& out, const MapFace& f) {
  const bool quote = f.quotedTexture || f.texture.empty() || f.texture.find_first_of(" \t\r\n") != std::string::npos;
  if (quote)
    fmt::format_to(std::back_inserter(out), "\"{}\"", f.texture);
  else
    out += f.texture;
}

void writeFace(std::string& out, const MapFace& f) {
  auto& P = f.points;
  fmt::format_to(std::back_inserter(out), "( {} {} {} ) ( {} {} {} ) ( {} {} {} ) ", P[0].x, P[0].y, P[0].z, P[1].x, P[1].y, P[1].z, P[2].x,
                 P[2].y, P[2].z);
  const TextureParams& t = f.tex;
  switch (t.kind) {
  case TextureKind::BrushPrimitive:
    fmt::format_to(std::back_inserter(out), "( ( {} {} {} ) ( {} {} {} ) ) ", t.matrix[0][0], t.matrix[0][1], t.matrix[0][2],
                   t.matrix[1][0], t.matrix[1][1], t.matrix[1][2]);
    writeTexture(out, f);
    break;
  case TextureKind::Valve220:
    writeTexture(out, f);
    fmt::format_to(std::back_inserter(out), " [ {} {} {} {} ] [ {} {} {} {} ] {} {} {}", t.axis[0].x, t.axis[0].y, t.axis[0].z, t.offset[0],
                   t.axis[1].x, t.axis[1].y, t.axis[1].z, t.offset[1], t.rotation, t.scale[0], t.scale[1]);
    break;
  case TextureKind::Standard:
    writeTexture(out, f);
    fmt::format_to(std::back_inserter(out), " {} {} {} {} {}", t.offset[0], t.offset[1], t.rotation, t.scale[0], t.scale[1]);
    break;
  }
  if (f.surface) fmt::format_to(std::back_inserter(out), " {} {} {}", f.surface->contents, f.surface->flags, f.surface->value);
  if (f.daikatanaColor)
    fmt::format_to(std::back_inserter(out), " {} {} {}", (*f.daikatanaColor)[0], (*f.daikatanaColor)[1], (*f.daikatanaColor)[2]);
  if (f.hexen2Value) fmt::format_to(std::back_inserter(out), " {}", *f.hexen2Value);
  if (!f.trailingComment.empty()) fmt::format_to(std::back_inserter(out), " {}", f.trailingComment);
  out += '\n';
}

void writeBrush(std::string& out, const MapBrush& b, size_t index) {
  fmt::format_to(std::back_inserter(out), "// brush {}\n{{\n", index);
  switch (b.kind) {
  case MapBrush::Kind::Verbatim: out += b.verbatim; break;
  case MapBrush::Kind::BrushDef:
    out += "brushDef\n{\n";
    for (const MapFace& f : b.faces) writeFace(out, f);
    out += "}\n";
    break;
  case MapBrush::Kind::Brush:
    for (const MapFace& f : b.faces) writeFace(out, f);
    break;
  }
  out += "}\n";
}

} // namespace

MapDocument convertDocument(const MapDocument& doc, MapDialect target, Diagnostics& report) {
  MapDocument out = doc;
  out.dialect = target;
  if (target == doc.dialect) return out;
  Converter converter(target, report, doc.path);
  for (MapEntity& e : out.entities)
    for (MapBrush& b : e.brushes) converter.convertBrush(b);
  return out;
}

std::string writeMap(const MapDocument& doc) {
  std::string out;
  out.reserve(1 << 16);
  fmt::format_to(std::back_inserter(out), "// Format: {}\n", formatName(doc.dialect));
  size_t entityIndex = 0;
  for (const MapEntity& e : doc.entities) {
    if (e.implicit) {
      // Clipboard files: bare brushes, written back without the entity we wrapped them in.
      for (size_t i = 0; i < e.brushes.size(); ++i) writeBrush(out, e.brushes[i], i);
      continue;
    }
    fmt::format_to(std::back_inserter(out), "// entity {}\n{{\n", entityIndex++);
    for (const auto& [k, v] : e.keys) fmt::format_to(std::back_inserter(out), "\"{}\" \"{}\"\n", k, v);
    for (size_t i = 0; i < e.brushes.size(); ++i) writeBrush(out, e.brushes[i], i);
    out += "}\n";
  }
  return out;
}

void writeFileAtomically(const std::string& path, const std::string& text) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  std::random_device rd;
  const fs::path temp = target.parent_path() / fmt::format(".{}.{:08x}.tmp", target.filename().string(), rd());
  auto fail = [&](const std::string& message) {
    std::error_code ec;
    fs::remove(temp, ec);
    throw ImportError(Diagnostic{Severity::Error, path, 0, 0, message});
  };
  {
    std::ofstream file(temp, std::ios::binary | std::ios::trunc);
    if (!file) fail("cannot create a temporary file beside it");
    file.write(text.data(), static_cast<std::streamsize>(text.size()));
    file.flush();
    if (!file) fail("cannot write the temporary file");
  }
  std::error_code ec;
  fs::rename(temp, target, ec);
  if (ec) fail(fmt::format("cannot rename the temporary file over it: {}", ec.message()));
}

} // namespace bt::map
