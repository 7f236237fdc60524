#include "importers/map/map_geometry.h"
#include "importers/map/map_parser.h"
#include "importers/map/map_scene.h"
#include "importers/map/map_writer.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace bt::map {
namespace {

const char* const kDialects[] = {"standard", "valve220", "quake2", "quake2-valve", "quake3", "quake3-valve", "hexen2", "daikatana"};

std::string dialectMap(const std::string& name) {
  return (bt::test::mapsDir() / "dialects" / (name + ".map")).string();
}

// The largest difference in texel coordinates between two imports of the same brushes, over
// every winding vertex.
double maxTexelDifference(const Scene& a, const Scene& b) {
  EXPECT_EQ(a.faces.size(), b.faces.size());
  double err = 0.0;
  for (size_t i = 0; i < std::min(a.faces.size(), b.faces.size()); ++i)
    for (const dvec3& p : a.faces[i].winding)
      err = std::max(
          {err, std::fabs(a.faces[i].frame.s(p) - b.faces[i].frame.s(p)), std::fabs(a.faces[i].frame.t(p) - b.faces[i].frame.t(p))});
  return err;
}

TEST(MapWriter, SameDialectRoundTripIsLosslessForEveryDialect) {
  for (const char* name : kDialects) {
    const MapDocument doc = readMapFile(dialectMap(name));
    Diagnostics report;
    const std::string text = writeMap(convertDocument(doc, doc.dialect, report));
    EXPECT_TRUE(report.empty()) << name;
    const MapDocument again = parseMap(text, "roundtrip.map");
    EXPECT_EQ(again, doc) << name << ":\n" << text;
  }
}

TEST(MapWriter, WritesShortestRoundTripDoublesAndQuotedNames) {
  MapDocument doc = parseMap("{\n{\n( 0.1 -0 1e-300 ) ( 0 1 0 ) ( 1 0 0 ) a 0 0 0 1 1\n}\n}\n", "t.map");
  doc.entities[0].brushes[0].faces[0].points[1].x = 1.0 / 3.0;
  doc.entities[0].brushes[0].faces[0].texture = "name with spaces";
  doc.entities[0].brushes[0].faces[0].quotedTexture = true; // spaces need quotes, as when read back
  const std::string text = writeMap(doc);
  EXPECT_NE(text.find("( 0.1 -0 1e-300 ) ( 0.3333333333333333 1 0 )"), std::string::npos) << text;
  EXPECT_NE(text.find("\"name with spaces\""), std::string::npos) << text;
  EXPECT_EQ(parseMap(text, "t.map"), doc);
}

TEST(MapWriter, WritesClipboardBrushesBackBare) {
  const MapDocument doc = parseMap("{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a 0 0 0 1 1\n}\n", "clip.map");
  const std::string text = writeMap(doc);
  EXPECT_EQ(text.find("classname"), std::string::npos) << text;
  EXPECT_EQ(parseMap(text, "clip.map"), doc);
}

TEST(MapWriter, StandardToValveIsTexelExact) {
  for (const char* name : {"standard", "quake2", "hexen2", "daikatana"}) {
    const MapDocument doc = readMapFile(dialectMap(name));
    Diagnostics report;
    const MapDocument valve = convertDocument(doc, MapDialect::Valve220, report);
    const MapDocument reread = parseMap(writeMap(valve), "v.map");
    EXPECT_EQ(reread.dialect, MapDialect::Valve220);
    for (const auto& e : reread.entities)
      for (const auto& b : e.brushes)
        for (const auto& f : b.faces) EXPECT_EQ(f.tex.kind, TextureKind::Valve220);
    EXPECT_LT(maxTexelDifference(buildScene(doc), buildScene(reread)), 0.01) << name;
  }
}

TEST(MapWriter, ValveToStandardIsExactWhereItCanBeAndReportsWhereNot) {
  const MapDocument doc = readMapFile(dialectMap("valve220"));
  Diagnostics report;
  const MapDocument standard = parseMap(writeMap(convertDocument(doc, MapDialect::Standard, report)), "s.map");
  EXPECT_TRUE(report.empty()) << format(report.at(0));
  EXPECT_LT(maxTexelDifference(buildScene(doc), buildScene(standard)), 0.01);

  // A sheared projection (axes not perpendicular) has no Standard equivalent: reported with its line.
  const MapDocument sheared = parseMap("{\n{\n( 0 0 0 ) ( 0 64 0 ) ( 0 0 64 ) a [ 0 1 0 0 ] [ 0 0.6 -0.8 0 ] 0 1 1\n( 0 0 0 ) ( 0 0 64 ) ( "
                                       "64 0 0 ) a [ 1 0 0 0 ] [ 0 0 -1 0 ] 0 1 1\n"
                                       "( 0 0 0 ) ( 64 0 0 ) ( 0 64 0 ) a [ 1 0 0 0 ] [ 0 -1 0 0 ] 0 1 1\n( 64 64 64 ) ( 64 0 64 ) ( 0 64 "
                                       "64 ) a [ 1 0 0 0 ] [ 0 -1 0 0 ] 0 1 1\n"
                                       "( 64 64 64 ) ( 0 64 64 ) ( 64 64 0 ) a [ 1 0 0 0 ] [ 0 0 -1 0 ] 0 1 1\n( 64 64 64 ) ( 64 64 0 ) ( "
                                       "64 0 64 ) a [ 0 1 0 0 ] [ 0 0 -1 0 ] 0 1 1\n}\n}\n",
                                       "shear.map");
  Diagnostics shearReport;
  convertDocument(sheared, MapDialect::Standard, shearReport);
  ASSERT_EQ(shearReport.size(), 1u);
  EXPECT_EQ(shearReport[0].line, 3);
  EXPECT_NE(shearReport[0].message.find("off by up to"), std::string::npos) << shearReport[0].message;
}

TEST(MapWriter, DropsFieldsTheTargetCannotHoldWithANote) {
  const MapDocument doc = readMapFile(dialectMap("quake2"));
  Diagnostics report;
  const MapDocument q1 = convertDocument(doc, MapDialect::Standard, report);
  EXPECT_FALSE(report.empty());
  for (const Diagnostic& d : report) EXPECT_EQ(d.severity, Severity::Note);
  EXPECT_FALSE(q1.entities[0].brushes[0].faces[0].surface);
}

TEST(MapWriter, WritesAtomicallyAndReplacesTheTarget) {
  const auto dir = std::filesystem::temp_directory_path() / "bt_map_writer_test";
  std::filesystem::create_directories(dir);
  const auto path = (dir / "out.map").string();
  writeFileAtomically(path, "first");
  writeFileAtomically(path, "second");
  std::ifstream in(path);
  std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(content, "second");
  size_t files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1u) << "no temporary file left behind";
  std::filesystem::remove_all(dir);
  EXPECT_THROW(writeFileAtomically((dir / "missing" / "x.map").string(), "x"), ImportError);
}

} // namespace
} // namespace bt::map
