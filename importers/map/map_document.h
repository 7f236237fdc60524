// A lossless model of a .map source file: what the file says, before any geometry is built.
//
// Every Quake-family editor writes the same skeleton, entities of "key" "value" pairs holding
// brushes of face lines,
//   ( x y z ) ( x y z ) ( x y z ) TEXTURE <texture parameters> [<extra fields>]
// and the dialects differ only in the texture parameters and the extra fields. The document
// keeps each face's parameters in the kind it was written in (a brush may mix Standard and
// Valve 220 lines, qbsp decides per face), so writing it back in the same dialect is lossless.
// Blocks we do not model (Quake 3 patchDef2/patchDef3, Doom 3 brushDef3, anything unknown)
// are kept as verbatim text.
#pragma once

#include "importers/import.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace bt::map {

// How a face line spells its texture projection.
enum class TextureKind {
  Standard,      // QuakeEd: offset x y, rotation, scale x y; axes from the paraxial table
  Valve220,      // [ ux uy uz offset ] [ vx vy vz offset ] rotation scale x y
  BrushPrimitive // Quake 3 brushDef: ( ( a b c ) ( d e f ) ), texture-space matrix
};

struct TextureParams {
  TextureKind kind = TextureKind::Standard;
  std::array<double, 2> offset{0.0, 0.0};        // Standard and Valve 220
  double rotation = 0.0;                         // Standard and Valve 220 (informative only for Valve)
  std::array<double, 2> scale{1.0, 1.0};         // Standard and Valve 220
  std::array<dvec3, 2> axis{};                   // Valve 220: U and V axes
  std::array<std::array<double, 3>, 2> matrix{}; // BrushPrimitive rows

  bool operator==(const TextureParams&) const = default;
};

struct MapFace {
  int line = 0;
  int column = 0;
  std::array<dvec3, 3> points{}; // as written; qbsp builds the plane from them
  std::string texture;
  bool quotedTexture = false; // written as "name" (names with spaces)
  TextureParams tex;
  // Quake 2 / Quake 3 / Daikatana: contents, surface flags, value
  std::optional<SurfaceAttributes> surface;
  std::optional<double> hexen2Value;                // Hexen II's one extra field
  std::optional<std::array<int, 3>> daikatanaColor; // Daikatana's surface colour after Q2 fields
  std::string trailingComment;                      // e.g. QuArK's "//TX1" at the end of the line

  // Equality is of content: where a face sits in the file (line, column) is not part of it,
  // so a rewritten file compares equal to its source.
  bool operator==(const MapFace& o) const {
    return points == o.points && texture == o.texture && quotedTexture == o.quotedTexture && tex == o.tex && surface == o.surface &&
        hexen2Value == o.hexen2Value && daikatanaColor == o.daikatanaColor && trailingComment == o.trailingComment;
  }
};

// A brush, a brushDef (Quake 3 brush primitives), or a block kept verbatim.
struct MapBrush {
  enum class Kind { Brush, BrushDef, Verbatim };
  Kind kind = Kind::Brush;
  int line = 0; // of the '{'
  int column = 0;
  int keywordLine = 0; // Kind::Verbatim: the line of the block's keyword, where `verbatim` starts
  std::vector<MapFace> faces;
  std::string verbatim; // Kind::Verbatim: the text between the brush's braces, exactly as read

  bool operator==(const MapBrush& o) const { return kind == o.kind && faces == o.faces && verbatim == o.verbatim; }
};

struct MapEntity {
  int line = 0;
  int column = 0;
  std::vector<std::pair<std::string, std::string>> keys; // file order, duplicates kept
  std::vector<MapBrush> brushes;
  // TrenchBroom's clipboard files hold bare brushes with no entity around them: they are
  // imported into an implicit worldspawn that the writer does not write back.
  bool implicit = false;

  bool operator==(const MapEntity& o) const { return keys == o.keys && brushes == o.brushes && implicit == o.implicit; }
};

struct MapDocument {
  std::string path;
  MapDialect dialect = MapDialect::Standard;
  bool dialectFromHeader = false; // a "// Format:" comment named it
  std::vector<MapEntity> entities;

  bool operator==(const MapDocument& other) const { return dialect == other.dialect && entities == other.entities; }
};

} // namespace bt::map
