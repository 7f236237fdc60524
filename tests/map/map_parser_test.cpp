#include "importers/map/map_parser.h"

#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <string>

namespace bt::map {
namespace {

MapDocument parse(const std::string& text, std::optional<MapDialect> forced = std::nullopt) {
  return parseMap(text, "test.map", forced);
}

// The message of the ImportError that parsing `text` throws, or "" if it does not throw.
std::string parseError(const std::string& text) {
  try {
    parse(text);
  } catch (const ImportError& e) {
    return e.what();
  }
  return "";
}

TEST(MapParser, ReadsAStandardFaceLineWithItsPosition) {
  const MapDocument doc =
      parse("{\n\"classname\" \"worldspawn\"\n{\n  ( 1 2 3 ) ( 4.5 -6 7e1 ) ( 0 0 1 ) WALL_1 16 -8 22.5 0.5 -2\n}\n}\n");
  ASSERT_EQ(doc.entities.size(), 1u);
  ASSERT_EQ(doc.entities[0].brushes.size(), 1u);
  const MapFace& f = doc.entities[0].brushes[0].faces.at(0);
  EXPECT_EQ(f.line, 4);
  EXPECT_EQ(f.column, 3);
  EXPECT_EQ(f.points[1], dvec3(4.5, -6, 70));
  EXPECT_EQ(f.texture, "WALL_1");
  EXPECT_EQ(f.tex.kind, TextureKind::Standard);
  EXPECT_EQ(f.tex.offset, (std::array<double, 2>{16, -8}));
  EXPECT_EQ(f.tex.rotation, 22.5);
  EXPECT_EQ(f.tex.scale, (std::array<double, 2>{0.5, -2}));
  EXPECT_FALSE(f.surface);
  EXPECT_EQ(doc.entities[0].brushes[0].line, 3);
  EXPECT_EQ(doc.dialect, MapDialect::Standard);
}

TEST(MapParser, ReadsValve220AndStandardLinesMixedInOneBrush) {
  const MapDocument doc = parse("{\n\"classname\" \"worldspawn\"\n{\n"
                                "( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a [ 1 0 0 4 ] [ 0 -1 0 8 ] 15 0.25 0.5\n"
                                "( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) b 1 2 3 4 5\n}\n}\n");
  const auto& faces = doc.entities[0].brushes[0].faces;
  ASSERT_EQ(faces.size(), 2u);
  EXPECT_EQ(faces[0].tex.kind, TextureKind::Valve220);
  EXPECT_EQ(faces[0].tex.axis[1], dvec3(0, -1, 0));
  EXPECT_EQ(faces[0].tex.offset, (std::array<double, 2>{4, 8}));
  EXPECT_EQ(faces[0].tex.scale, (std::array<double, 2>{0.25, 0.5}));
  EXPECT_EQ(faces[1].tex.kind, TextureKind::Standard);
  EXPECT_EQ(doc.dialect, MapDialect::Valve220); // detected from the Valve axes
}

TEST(MapParser, ReadsSurfaceFieldsHexen2AndDaikatanaExtras) {
  const MapDocument doc = parse("{\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) e1u1/floor 0 0 0 1 1 1 16 200\n"
                                "( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) rtex 0 0 0 1 1 7\n"
                                "( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) dk 0 0 0 1 1 8 4 2 255 128 64\n}\n}\n");
  const auto& f = doc.entities[0].brushes[0].faces;
  ASSERT_TRUE(f[0].surface);
  EXPECT_EQ(*f[0].surface, (SurfaceAttributes{1, 16, 200}));
  EXPECT_EQ(f[0].texture, "e1u1/floor");
  EXPECT_EQ(f[1].hexen2Value, 7.0);
  EXPECT_FALSE(f[1].surface);
  ASSERT_TRUE(f[2].daikatanaColor);
  EXPECT_EQ(*f[2].daikatanaColor, (std::array<int, 3>{255, 128, 64}));
  EXPECT_EQ(doc.dialect, MapDialect::Daikatana);
}

TEST(MapParser, ReadsBrushDefAndKeepsPatchesVerbatim) {
  const std::string patch = "patchDef2\n{\ncurve\n( 3 3 0 0 0 )\n(\n( ( 0 0 0 0 0 ) ( 1 0 0 1 0 ) ( 2 0 0 2 0 ) )\n)\n}\n";
  const MapDocument doc = parse("{\n\"classname\" \"worldspawn\"\n{\nbrushDef\n{\n"
                                "( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) ( ( 0.5 0 0.25 ) ( 0 0.5 0 ) ) tex/x 0 0 0\n}\n}\n{\n" +
                                patch + "}\n}\n");
  const auto& brushes = doc.entities[0].brushes;
  ASSERT_EQ(brushes.size(), 2u);
  EXPECT_EQ(brushes[0].kind, MapBrush::Kind::BrushDef);
  EXPECT_EQ(brushes[0].faces[0].tex.kind, TextureKind::BrushPrimitive);
  EXPECT_EQ(brushes[0].faces[0].tex.matrix[0][2], 0.25);
  EXPECT_EQ(brushes[0].faces[0].texture, "tex/x");
  EXPECT_EQ(brushes[1].kind, MapBrush::Kind::Verbatim);
  EXPECT_EQ(brushes[1].verbatim, patch);
  EXPECT_EQ(brushes[1].line, 9);
  EXPECT_EQ(doc.dialect, MapDialect::Quake3);
}

TEST(MapParser, KeepsKeysInOrderWithDuplicatesAndOddCharacters) {
  const MapDocument doc = parse("{\n\"classname\" \"light\"\n\"target\" \"a\"\n\"target\" \"b { } // ;\"\n\"_tb_layer\" \"1\"\n}\n");
  const auto& keys = doc.entities[0].keys;
  ASSERT_EQ(keys.size(), 4u);
  EXPECT_EQ(keys[1], (std::pair<std::string, std::string>{"target", "a"}));
  EXPECT_EQ(keys[2].second, "b { } // ;");
  EXPECT_EQ(keys[3].first, "_tb_layer");
}

TEST(MapParser, SkipsQuarkAndSlashCommentsAndKeepsQuarkTxMarkers) {
  const MapDocument doc = parse("; QuArK header\n// a comment\n{\n; Entity 0\n\"classname\" \"worldspawn\"\n{\n"
                                "( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) sand 0 0 0 1 1 //TX1\n}\n}\n");
  const MapFace& f = doc.entities[0].brushes[0].faces.at(0);
  EXPECT_EQ(f.trailingComment, "//TX1");
  EXPECT_EQ(f.line, 7);
}

TEST(MapParser, PutsClipboardBrushesIntoAnImplicitWorldspawn) {
  const MapDocument doc = parse("{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a 0 0 0 1 1\n}\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) b 0 0 0 1 1\n}\n");
  ASSERT_EQ(doc.entities.size(), 1u);
  EXPECT_TRUE(doc.entities[0].implicit);
  EXPECT_EQ(doc.entities[0].brushes.size(), 2u);
  EXPECT_EQ(doc.entities[0].keys.at(0).second, "worldspawn");
}

TEST(MapParser, DetectsDialectFromHeaderKeysAndFaceLines) {
  EXPECT_EQ(parse("// Game: Quake 2\n// Format: Quake2 (Valve)\n{\n}\n").dialect, MapDialect::Quake2Valve);
  EXPECT_TRUE(parse("// Format: Hexen2\n").dialectFromHeader);
  // A Quake 1 format under a Quake 2 game is its Quake 2 form (ericw-tools' q2_hdrtest.map).
  EXPECT_EQ(parse("// Game: Quake 2\n// Format: Valve\n{\n}\n").dialect, MapDialect::Quake2Valve);
  EXPECT_EQ(parse("// Game: Quake 2\n// Format: Standard\n{\n}\n").dialect, MapDialect::Quake2);
  EXPECT_EQ(parse("// Game: Quake\n// Format: Valve\n{\n}\n").dialect, MapDialect::Valve220);
  EXPECT_EQ(parse("{\n\"mapversion\" \"220\"\n}\n").dialect, MapDialect::Valve220);
  EXPECT_EQ(parse("{\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a 0 0 0 1 1 0 0 0\n}\n}\n").dialect, MapDialect::Quake2);
  EXPECT_EQ(parse("{\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a [ 1 0 0 0 ] [ 0 1 0 0 ] 0 1 1 0 0 0\n}\n}\n").dialect, MapDialect::Quake2Valve);
  EXPECT_EQ(parse("{\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a 0 0 0 1 1 0\n}\n}\n").dialect, MapDialect::Hexen2);
  EXPECT_EQ(parse("{\n{\npatchDef2\n{\n}\n}\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a 0 0 0 1 1 0 0 0\n}\n}\n").dialect, MapDialect::Quake3);
  EXPECT_EQ(parse("{\n}\n", MapDialect::Daikatana).dialect, MapDialect::Daikatana);
  EXPECT_EQ(parse("").entities.size(), 0u);
}

TEST(MapParser, ReportsTruncatedFilesWithLineAndColumn) {
  EXPECT_EQ(parseError("{\n\"classname\" \"worldspawn\"\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a 0 0"),
            "test.map:4:36: error: unexpected end of file, expected texture rotation");
  EXPECT_EQ(parseError("{\n\"classname\" \"worldspawn\"\n"),
            "test.map:1:1: error: unexpected end of file: this entity's '{' is never closed");
  EXPECT_EQ(parseError("{\n\"classname\" \"worl"), "test.map:2:13: error: unterminated string (value of key \"classname\")");
}

TEST(MapParser, ReportsUnbalancedBracesBadNumbersAndGarbage) {
  EXPECT_EQ(parseError("{\n}\n}\n"), "test.map:3:1: error: expected '{' to open an entity, found '}'");
  EXPECT_EQ(parseError("{\n{\n( 0 0 0 ) ( 0 1x 0 ) ( 1 0 0 ) a 0 0 0 1 1\n}\n}\n"),
            "test.map:3:15: error: bad number '1x' for plane point y");
  EXPECT_EQ(parseError("{\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a 0 0 0 1 nan\n}\n}\n"),
            "test.map:3:41: error: bad number 'nan' for texture scale y");
  EXPECT_EQ(parseError("{\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a 0 0 0 1 1 0 0\n}\n}\n"),
            "test.map:3:43: error: 2 fields after the texture parameters: expected none, 1 (Hexen II), 3 (Quake 2 contents, flags, value) "
            "or 6 (Daikatana)");
  EXPECT_EQ(parseError(std::string("\x7f"
                                   "ELF\x02\x01\x01\0\0\0",
                                   10)),
            "test.map:1:1: error: expected '{' to open an entity, found byte 0x7f");
  EXPECT_EQ(parseError(std::string("{\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a\x01\x02 0 0 0 1 1\n}\n}\n")),
            "test.map:3:32: error: unexpected byte 0x01 in texture name");
}

TEST(MapParser, SurvivesAHundredMegabyteLine) {
  std::string text = "{\n\"classname\" \"worldspawn\"\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a 0 0 0 1 ";
  text.append(100u << 20, '7');
  const std::string error = parseError(text);
  EXPECT_EQ(error.substr(0, 58), "test.map:4:41: error: bad number '777777777777777777777777");
}

TEST(MapParser, ReadsEveryDialectMapWeWrote) {
  for (const char* name : {"standard", "valve220", "quake2", "quake2-valve", "quake3", "quake3-valve", "hexen2", "daikatana"}) {
    const std::string path = (bt::test::mapsDir() / "dialects" / (std::string(name) + ".map")).string();
    const MapDocument doc = readMapFile(path);
    EXPECT_EQ(toString(doc.dialect), std::string(name)) << path;
    EXPECT_EQ(detectDialect(doc), doc.dialect) << "the face lines alone must say the same as the header: " << path;
    EXPECT_EQ(doc.entities.size(), 3u) << path;
  }
}

} // namespace
} // namespace bt::map
