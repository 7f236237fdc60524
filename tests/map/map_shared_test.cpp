// Every community map under ../shared/maps imports and round-trips losslessly.
#include "importers/map/map_parser.h"
#include "importers/map/map_scene.h"
#include "importers/map/map_writer.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <set>

namespace bt::map {
namespace {

std::vector<std::filesystem::path> sharedMaps(const std::filesystem::path& shared) {
  std::vector<std::filesystem::path> maps;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(shared / "maps"))
    if (entry.is_regular_file() && entry.path().extension() == ".map") maps.push_back(entry.path());
  std::sort(maps.begin(), maps.end());
  return maps;
}

TEST(SharedMaps, EveryMapImportsAndRoundTripsLosslessly) {
  BT_REQUIRE_SHARED(shared);
  const auto maps = sharedMaps(shared);
  EXPECT_EQ(maps.size(), 234u);
  size_t faces = 0;
  for (const auto& path : maps) {
    SCOPED_TRACE(path.string());
    MapDocument doc;
    ASSERT_NO_THROW(doc = readMapFile(path.string()));
    const Scene scene = buildScene(doc);
    faces += scene.faces.size();
    for (const Diagnostic& d : scene.diagnostics) EXPECT_GT(d.line, d.severity == Severity::Note ? -1 : 0) << format(d);

    Diagnostics report;
    const std::string text = writeMap(convertDocument(doc, doc.dialect, report));
    EXPECT_TRUE(report.empty());
    MapDocument again;
    ASSERT_NO_THROW(again = parseMap(text, path.string() + " (rewritten)"));
    EXPECT_TRUE(again == doc) << "round trip changed the document";
  }
  EXPECT_GT(faces, 100000u);
}

// Largest texel difference between two scenes built from the same brushes, at every winding vertex.
double maxTexelDifference(const Scene& a, const Scene& b) {
  double err = 0.0;
  for (size_t i = 0; i < a.faces.size(); ++i)
    for (const dvec3& p : a.faces[i].winding)
      err = std::max(
          {err, std::fabs(a.faces[i].frame.s(p) - b.faces[i].frame.s(p)), std::fabs(a.faces[i].frame.t(p) - b.faces[i].frame.t(p))});
  return err;
}

TEST(SharedMaps, StandardToValveIsTexelExactAndValveToStandardReportsWhatItCannotKeep) {
  BT_REQUIRE_SHARED(shared);
  size_t standardMaps = 0, valveMaps = 0, facesReported = 0, valveFaces = 0;
  for (const auto& path : sharedMaps(shared)) {
    SCOPED_TRACE(path.string());
    const MapDocument doc = readMapFile(path.string());
    if (doc.dialect == MapDialect::Standard) {
      ++standardMaps;
      Diagnostics report;
      const MapDocument valve =
          parseMap(writeMap(convertDocument(doc, MapDialect::Valve220, report)), path.string()); // the same folder: prefabs resolve alike
      const Scene before = buildScene(doc);
      const Scene after = buildScene(valve);
      ASSERT_EQ(before.faces.size(), after.faces.size());
      EXPECT_LT(maxTexelDifference(before, after), 0.01);
    } else if (doc.dialect == MapDialect::Valve220) {
      ++valveMaps;
      Diagnostics report;
      const MapDocument standard = parseMap(writeMap(convertDocument(doc, MapDialect::Standard, report)), path.string());
      const Scene before = buildScene(doc);
      const Scene after = buildScene(standard);
      ASSERT_EQ(before.faces.size(), after.faces.size());
      // Every face that moved by more than 0.01 texel must have been reported, with its line.
      std::set<int> reportedLines;
      for (const Diagnostic& d : report)
        if (d.severity == Severity::Warning) reportedLines.insert(d.line);
      facesReported += reportedLines.size();
      valveFaces += before.faces.size();
      for (size_t i = 0; i < before.faces.size(); ++i) {
        double err = 0.0;
        for (const dvec3& p : before.faces[i].winding)
          err = std::max({err, std::fabs(before.faces[i].frame.s(p) - after.faces[i].frame.s(p)),
                          std::fabs(before.faces[i].frame.t(p) - after.faces[i].frame.t(p))});
        if (err > 0.01) {
          EXPECT_TRUE(reportedLines.count(before.faces[i].line)) << "face on line " << before.faces[i].line << " off by " << err;
        }
      }
    }
  }
  EXPECT_GT(standardMaps, 40u);
  EXPECT_GT(valveMaps, 80u);
  std::cout << "Valve 220 -> Standard: " << facesReported << " of " << valveFaces << " faces reported as not representable\n";
}

} // namespace
} // namespace bt::map
