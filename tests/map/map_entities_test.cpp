// Brush entities as qbsp compiles them (brush_entities.h): misc_external_map prefabs placed and
// retyped, origin brushes giving the model origin, Hipnotic rotators taking their target's.
#include "importers/map/brush_entities.h"
#include "importers/map/map_parser.h"
#include "importers/map/map_scene.h"
#include "importers/map/map_writer.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace bt::map {
namespace {

namespace fs = std::filesystem;

// An axis-aligned box brush from lo to hi, faces in TrenchBroom's order, Standard texturing `tail`.
std::string box(const dvec3& lo, const dvec3& hi, const std::string& tail) {
  auto p = [](double x, double y, double z) { return fmt::format("( {} {} {} )", x, y, z); };
  std::string s = "{\n";
  s += p(lo.x, lo.y, lo.z) + " " + p(lo.x, lo.y + 1, lo.z) + " " + p(lo.x, lo.y, lo.z + 1) + " " + tail + "\n";
  s += p(lo.x, lo.y, lo.z) + " " + p(lo.x, lo.y, lo.z + 1) + " " + p(lo.x + 1, lo.y, lo.z) + " " + tail + "\n";
  s += p(lo.x, lo.y, lo.z) + " " + p(lo.x + 1, lo.y, lo.z) + " " + p(lo.x, lo.y + 1, lo.z) + " " + tail + "\n";
  s += p(hi.x, hi.y, hi.z) + " " + p(hi.x, hi.y - 1, hi.z) + " " + p(hi.x - 1, hi.y, hi.z) + " " + tail + "\n";
  s += p(hi.x, hi.y, hi.z) + " " + p(hi.x - 1, hi.y, hi.z) + " " + p(hi.x, hi.y, hi.z - 1) + " " + tail + "\n";
  s += p(hi.x, hi.y, hi.z) + " " + p(hi.x, hi.y, hi.z - 1) + " " + p(hi.x, hi.y - 1, hi.z) + " " + tail + "\n";
  return s + "}\n";
}

// A folder of its own under the system's temporary one, removed afterwards.
class TempDir {
public:
  TempDir() {
    path_ = fs::temp_directory_path() /
        fmt::format("bt_entities_{}_{}", ::testing::UnitTest::GetInstance()->current_test_info()->name(), static_cast<const void*>(this));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path file = path_ / name;
    fs::create_directories(file.parent_path());
    std::ofstream(file) << text;
    return file.string();
  }

private:
  fs::path path_;
};

const std::string kWorld = "{\n\"classname\" \"worldspawn\"\n}\n";

TEST(BrushEntities, ExternalMapPlacementScalesThenRotatesThenMovesLikeQbsp) {
  std::vector<std::string> warnings;
  auto place = [&](std::vector<std::pair<std::string, std::string>> keys) { return externalMapPlacement(keys, warnings); };
  auto near = [](const dvec3& a, const dvec3& b) { return glm::length(a - b) < 1e-12; };
  // Right-handed rotations, as qbsp's RotateAboutZ/Y/X: yaw turns +X to +Y, pitch +X to -Z, roll +Y to +Z.
  EXPECT_TRUE(near(place({{"_external_map_angles", "0 90 0"}}).apply(dvec3(1, 0, 0)), dvec3(0, 1, 0)));
  EXPECT_TRUE(near(place({{"_external_map_angles", "0 -270 0"}}).apply(dvec3(1, 0, 0)), dvec3(0, 1, 0)));
  EXPECT_TRUE(near(place({{"_external_map_angles", "0 45 0"}}).apply(dvec3(2, 0, 0)), dvec3(std::sqrt(2.0), std::sqrt(2.0), 0)));
  EXPECT_TRUE(near(place({{"_external_map_angle", "90"}}).apply(dvec3(1, 0, 0)), dvec3(0, 1, 0)));
  EXPECT_TRUE(near(place({{"_external_map_angles", "90 0 0"}}).apply(dvec3(1, 0, 0)), dvec3(0, 0, -1)));
  EXPECT_TRUE(near(place({{"_external_map_angles", "0 0 90"}}).apply(dvec3(0, 1, 0)), dvec3(0, 0, 1)));
  // "angles" wins over "angle" unless it is all zero.
  EXPECT_TRUE(near(place({{"_external_map_angles", "0 180 0"}, {"_external_map_angle", "90"}}).apply(dvec3(1, 0, 0)), dvec3(-1, 0, 0)));
  // Scale first, in the prefab's axes; then rotation; then the origin.
  const Placement p = place({{"origin", "100 0 8"}, {"_external_map_angle", "90"}, {"_external_map_scale", "2 1 1"}});
  EXPECT_TRUE(near(p.apply(dvec3(1, 0, 0)), dvec3(100, 2, 8)));
  EXPECT_TRUE(near(place({{"_external_map_scale", "3"}}).apply(dvec3(1, 1, 1)), dvec3(3, 3, 3)));
  EXPECT_TRUE(warnings.empty());
  EXPECT_TRUE(near(place({{"_external_map_scale", "0 1 1"}}).apply(dvec3(1, 1, 1)), dvec3(1, 1, 1)));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("zero"), std::string::npos);
}

TEST(BrushEntities, ExternalMapBrushesArePlacedRetypedAndKeepTheirTextures) {
  TempDir dir;
  // The prefab: a 64-unit box in a Valve 220 file with a rotated, scaled texture, and a
  // func_detail whose brush qbsp also takes.
  const std::string prefab = dir.write(
      "prefabs/crate.map",
      "{\n\"classname\" \"worldspawn\"\n\"mapversion\" \"220\"\n" + box({0, 0, 0}, {64, 64, 64}, "crate [ 1 1 0 3 ] [ 0 0 -1 5 ] 0 0.5 2") +
          "}\n{\n\"classname\" \"func_detail\"\n" + box({0, 0, 64}, {16, 16, 80}, "crate [ 1 0 0 0 ] [ 0 -1 0 0 ] 0 1 1") + "}\n");
  const std::string main =
      dir.write("level.map",
                kWorld +
                    "{\n\"classname\" \"misc_external_map\"\n\"origin\" \"100 0 8\"\n\"_external_map\" \"prefabs/crate.map\"\n"
                    "\"_external_map_classname\" \"func_wall\"\n\"_external_map_angle\" \"90\"\n\"_external_map_scale\" \"2 1 "
                    "1\"\n\"targetname\" \"w\"\n}\n");
  const MapDocument doc = readMapFile(main);
  const Scene scene = buildScene(doc);
  const Scene source = buildScene(readMapFile(prefab));
  ASSERT_EQ(scene.entities.size(), 2u);
  const Entity& wall = scene.entities[1];
  EXPECT_EQ(wall.classname(), "func_wall");
  EXPECT_EQ(wall.value("origin"), "0 0 0");
  EXPECT_EQ(wall.value("targetname"), "w"); // the other keys stay for the new class
  ASSERT_EQ(wall.brushCount, 2u);
  ASSERT_EQ(scene.faces.size(), source.faces.size());
  // Box x 0..64 scaled to 0..128, turned 90 degrees (x -> y, y -> -x), moved to (100, 0, 8).
  // Right angles are exact, so integer corners stay integers.
  EXPECT_EQ(scene.brushes[wall.firstBrush].bounds.min, dvec3(36, 0, 8));
  EXPECT_EQ(scene.brushes[wall.firstBrush].bounds.max, dvec3(100, 128, 72));

  // Texture lock: every placed corner has the texel coordinates its source corner had.
  const Placement placement = [&] {
    std::vector<std::string> unused;
    return externalMapPlacement(doc.entities[1].keys, unused);
  }();
  for (size_t i = 0; i < source.faces.size(); ++i) {
    const Face& from = source.faces[i];
    const Face& to = scene.faces[i];
    ASSERT_EQ(from.winding.size(), to.winding.size());
    for (const dvec3& p : from.winding) {
      const dvec3 q = placement.apply(p);
      EXPECT_NEAR(to.plane.distanceTo(q), 0.0, 1e-9);
      EXPECT_NEAR(to.frame.s(q), from.frame.s(p), 1e-9);
      EXPECT_NEAR(to.frame.t(q), from.frame.t(p), 1e-9);
    }
    EXPECT_NEAR(to.plane.distanceTo(to.frame.origin), 0.0, 1e-9);
  }
  // The document is untouched: writing it gives back the misc_external_map as written.
  EXPECT_EQ(parseMap(writeMap(doc), main), doc);
  EXPECT_NE(writeMap(doc).find("\"classname\" \"misc_external_map\""), std::string::npos);
}

// The viewer watches Scene::inputFiles: a saved prefab must reload the level that includes it.
TEST(BrushEntities, TheImportListsTheMapAndEachExternalMapAsInputFiles) {
  TempDir dir;
  const std::string prefab =
      dir.write("prefabs/crate.map", kWorld.substr(0, kWorld.size() - 2) + box({0, 0, 0}, {8, 8, 8}, "a 0 0 0 1 1") + "}\n");
  dir.write("prefabs/unused.map", kWorld); // beside it, never named: not listed
  const std::string placement = "{\n\"classname\" \"misc_external_map\"\n\"_external_map\" \"prefabs/crate.map\"\n"
                                "\"_external_map_classname\" \"func_group\"\n}\n";
  const std::string main = dir.write("level.map", kWorld + placement + placement);
  ImportOptions options;
  options.textures.load = false;
  const Scene scene = importMap(main, options);
  ASSERT_EQ(scene.entities.size(), 3u);
  ASSERT_EQ(scene.inputFiles.size(), 2u) << "the map, then the prefab once however often it is placed";
  EXPECT_EQ(scene.inputFiles[0], main);
  EXPECT_EQ(fs::path(scene.inputFiles[1]).lexically_normal(), fs::path(prefab).lexically_normal());
}

TEST(BrushEntities, NestedExternalMapsAreNotFollowedSoSelfReferenceEnds) {
  TempDir dir;
  // A prefab that includes itself: qbsp takes its brushes and ignores its point entities.
  dir.write(
      "self.map",
      kWorld.substr(0, kWorld.size() - 2) + box({0, 0, 0}, {8, 8, 8}, "a 0 0 0 1 1") +
          "}\n{\n\"classname\" \"misc_external_map\"\n\"_external_map\" \"self.map\"\n\"_external_map_classname\" \"func_group\"\n}\n");
  const std::string main = dir.write("level.map",
                                     kWorld +
                                         "{\n\"classname\" \"misc_external_map\"\n\"_external_map\" \"self.map\"\n"
                                         "\"_external_map_classname\" \"func_group\"\n}\n");
  const Scene scene = buildScene(readMapFile(main));
  ASSERT_EQ(scene.entities.size(), 2u);
  EXPECT_EQ(scene.entities[1].classname(), "func_group");
  EXPECT_EQ(scene.entities[1].brushCount, 1u);
  bool noted = false;
  for (const Diagnostic& d : scene.diagnostics)
    noted |=
        d.severity == Severity::Note && d.file.ends_with("self.map") && d.line == 12 && d.message.find("not followed") != std::string::npos;
  EXPECT_TRUE(noted);
}

TEST(BrushEntities, BadExternalMapsStopTheImportNamingFileLineAndColumn) {
  TempDir dir;
  const std::string entity = "{\n\"classname\" \"misc_external_map\"\n\"_external_map_classname\" \"func_group\"\n";
  auto error = [](const std::string& path) -> std::string {
    try {
      buildScene(readMapFile(path));
    } catch (const ImportError& e) {
      return e.what();
    }
    return "no error";
  };
  // No file named: the entity's position in the including map.
  const std::string noKey = dir.write("nokey.map", kWorld + entity + "}\n");
  EXPECT_EQ(error(noKey), noKey + ":4:1: error: misc_external_map without an \"_external_map\" key naming the .map to include");
  // A file that is not there.
  const std::string missing = dir.write("missing.map", kWorld + entity + "\"_external_map\" \"gone.map\"\n}\n");
  EXPECT_NE(error(missing).find(missing + ":4:1: error: misc_external_map: \"_external_map\" \"gone.map\" not found"), std::string::npos);
  // A malformed prefab: its own file, line and column, and who included it.
  const std::string broken =
      dir.write("broken.map", "{\n\"classname\" \"worldspawn\"\n{\n( 0 0 0 ) ( 1 0 0 ) ( 0 oops 0 ) a 0 0 0 1 1\n}\n}\n");
  const std::string includer = dir.write("includer.map", kWorld + entity + "\"_external_map\" \"broken.map\"\n}\n");
  const std::string message = error(includer);
  EXPECT_EQ(message.rfind(broken + ":4:", 0), 0u) << message;
  EXPECT_NE(message.find("(in the external map of the misc_external_map at " + includer + ":4)"), std::string::npos) << message;
}

// Found by tests/fuzz/fuzz_map: a name the file system cannot even look up (longer than a file
// name may be) threw std::filesystem::filesystem_error out of buildScene.
TEST(BrushEntities, ExternalMapNameTooLongToLookUpIsNotFound) {
  const std::string name(5000, 'x');
  const std::string text =
      "{\n\"classname\" \"worldspawn\"\n}\n{\n\"classname\" \"misc_external_map\"\n\"_external_map\" \"" + name + ".map\"\n}\n";
  try {
    buildScene(parseMap(text, "long.map"));
    FAIL() << "no error";
  } catch (const ImportError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("long.map:4:1: error: misc_external_map: \"_external_map\" \"" + name + ".map\" not found", 0),
              0u);
    EXPECT_NE(std::string(e.what()).find("File name too long"), std::string::npos) << e.what();
  }
}

TEST(BrushEntities, OriginBrushGivesTheModelOriginAndTheBrushesStayInPlace) {
  // A door with an origin brush centred on (8, 16, 24); qbsp writes that origin and compiles the
  // model around it, so the engine draws the door where the source has it.
  const std::string text = kWorld + "{\n\"classname\" \"func_door_rotating\"\n\"origin\" \"1 1 1\"\n" +
      box({0, 0, 0}, {64, 8, 96}, "door 0 0 0 1 1") + box({0, 8, 16}, {16, 24, 32}, "ORIGIN 0 0 0 1 1") +
      "}\n{\n\"classname\" \"func_group\"\n" + box({0, 0, 0}, {8, 8, 8}, "origin 0 0 0 1 1") + "}\n";
  const Scene scene = buildScene(parseMap(text, "door.map"));
  ASSERT_EQ(scene.entities.size(), 3u);
  EXPECT_EQ(scene.entities[1].value("origin"), "8 16 24"); // replaces the written one, as in qbsp
  EXPECT_EQ(scene.brushes[scene.entities[1].firstBrush].bounds.min, dvec3(0, 0, 0));
  EXPECT_EQ(scene.brushes[scene.entities[1].firstBrush].bounds.max, dvec3(64, 8, 96));
  // Brushes that join the world have no model, so no origin: noted, nothing set.
  EXPECT_EQ(scene.entities[2].find("origin"), nullptr);
  ASSERT_FALSE(scene.diagnostics.empty());
  EXPECT_EQ(scene.diagnostics.back().line, 24);
  EXPECT_NE(scene.diagnostics.back().message.find("origin brush of 'func_group' ignored"), std::string::npos);
}

TEST(BrushEntities, QuakeTwoOriginBrushesGoByTheirContents) {
  MapBrush brush;
  brush.faces.resize(1);
  brush.faces[0].texture = "e1u1/origin";
  EXPECT_TRUE(isOriginBrush(brush)); // no contents written: the texture (its .wal) decides
  brush.faces[0].surface = SurfaceAttributes{1, 0, 0.0};
  EXPECT_FALSE(isOriginBrush(brush)); // written solid
  brush.faces[0].texture = "e1u1/wall";
  brush.faces[0].surface = SurfaceAttributes{0x01000000, 0, 0.0};
  EXPECT_TRUE(isOriginBrush(brush)); // CONTENTS_ORIGIN, whatever the name
}

TEST(BrushEntities, HipnoticRotatorsTakeTheirTargetsOrigin) {
  const std::string text = kWorld + "{\n\"classname\" \"rotate_object\"\n\"target\" \"pivot\"\n" +
      box({0, 0, 0}, {8, 8, 8}, "a 0 0 0 1 1") + "}\n{\n\"classname\" \"rotate_door\"\n" + box({0, 0, 0}, {8, 8, 8}, "a 0 0 0 1 1") +
      "}\n{\n\"classname\" \"info_rotate\"\n\"targetname\" \"PIVOT\"\n\"origin\" \"4 -4 2.5\"\n}\n";
  const Scene scene = buildScene(parseMap(text, "rot.map"));
  ASSERT_EQ(scene.entities.size(), 4u);
  EXPECT_EQ(scene.entities[1].value("origin"), "4 -4 2.5"); // the target comes later in the file
  EXPECT_EQ(scene.entities[2].value("origin"), "0 0 0");    // no target: qbsp warns and uses 0 0 0
  ASSERT_FALSE(scene.diagnostics.empty());
  EXPECT_NE(scene.diagnostics.back().message.find("'rotate_door' has no origin brush and no target"), std::string::npos);
}

} // namespace
} // namespace bt::map
