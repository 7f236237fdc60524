// Every community map under ../shared/maps imports and round-trips losslessly.
#include "importers/map/map_parser.h"
#include "importers/map/map_scene.h"
#include "importers/map/map_writer.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

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

} // namespace
} // namespace bt::map
