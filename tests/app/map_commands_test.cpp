// The info, dump and convert commands, run as a user runs them: the built executable.
#include "tests/app/run_command.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace {

using bt::test::brushtrace;
using bt::test::CommandResult;

std::string readFile(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string dialectMap(const char* name) {
  return (bt::test::mapsDir() / "dialects" / (std::string(name) + ".map")).string();
}

TEST(DumpCommand, PrintsTheDocumentedSchema) {
  const CommandResult r = brushtrace("dump --json '" + dialectMap("valve220") + "'");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("dialect"), "valve220");
  ASSERT_EQ(j.at("entities").size(), 3u);
  const auto& world = j["entities"][0];
  EXPECT_EQ(world.at("classname"), "worldspawn");
  EXPECT_EQ(world.at("line"), 5);
  EXPECT_EQ(world.at("keys")[1], nlohmann::json::array({"mapversion", "220"}));
  const auto& face = world.at("brushes")[0].at("faces")[3]; // the floor brush's top
  EXPECT_EQ(face.at("texture"), "floor_1");
  EXPECT_EQ(face.at("normal"), nlohmann::json::array({0.0, 0.0, 1.0}));
  EXPECT_EQ(face.at("dist"), 0.0);
  EXPECT_EQ(face.at("line"), 15);
  EXPECT_EQ(face.at("winding").size(), 4u);
  for (const char* key : {"origin", "tangent", "bitangent"}) EXPECT_EQ(face.at(key).size(), 3u) << key;
  // Duplicate keys stay, in file order.
  const auto& door = j["entities"][2];
  EXPECT_EQ(door.at("keys")[2][0], "targetname");
  EXPECT_EQ(door.at("keys")[3][0], "targetname");
}

// JSON is dump's only format, so --json is optional: the same output with and without it.
TEST(DumpCommand, PrintsJsonWithoutTheFlagAndReportsBadInputWithPosition) {
  const CommandResult plain = brushtrace("dump '" + dialectMap("standard") + "'");
  ASSERT_EQ(plain.exitCode, 0) << plain.err;
  EXPECT_EQ(nlohmann::json::parse(plain.out).at("dialect"), "standard");
  EXPECT_EQ(plain.out, brushtrace("dump --json '" + dialectMap("standard") + "'").out);
  const auto bad = std::filesystem::temp_directory_path() / "bt_app_bad.map";
  std::ofstream(bad) << "{\n\"classname\" \"worldspawn\"\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a 0 zero 0 1 1\n}\n}\n";
  const CommandResult r = brushtrace("dump --json '" + bad.string() + "'");
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find(bad.string() + ":4:35: error: bad number 'zero'"), std::string::npos) << r.err;
  std::filesystem::remove(bad);
}

TEST(InfoCommand, SummarisesDialectCountsTexturesAndInvalidBrushes) {
  const auto path = std::filesystem::temp_directory_path() / "bt_app_info.map";
  std::ofstream(path) << "// Format: Standard\n{\n\"classname\" \"worldspawn\"\n{\n( 0 0 0 ) ( 0 64 0 ) ( 0 0 64 ) a 0 0 0 1 1\n"
                         "( 0 0 0 ) ( 0 0 64 ) ( 0 64 0 ) b 0 0 0 1 1\n}\n}\n";
  const CommandResult r = brushtrace("info --json --no-textures '" + path.string() + "'");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("dialect"), "standard");
  EXPECT_EQ(j.at("entities"), 1);
  EXPECT_EQ(j.at("brushes"), 0);
  ASSERT_EQ(j.at("problems").size(), 1u);
  EXPECT_EQ(j["problems"][0].at("line"), 4);

  const CommandResult text = brushtrace("info '" + dialectMap("quake2") + "'");
  ASSERT_EQ(text.exitCode, 0) << text.err;
  EXPECT_NE(text.out.find("dialect   quake2"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("brushes   4"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("floor_1"), std::string::npos) << text.out;
  std::filesystem::remove(path);
}

TEST(ConvertCommand, ConvertsRefusesToOverwriteItsInputAndWritesInPlaceWhenAsked) {
  const auto dir = std::filesystem::temp_directory_path() / "bt_app_convert";
  std::filesystem::create_directories(dir);
  const auto in = dir / "in.map";
  std::filesystem::copy_file(dialectMap("standard"), in, std::filesystem::copy_options::overwrite_existing);
  const std::string before = readFile(in);

  const CommandResult refused = brushtrace("convert '" + in.string() + "' -o '" + in.string() + "' --dialect valve220");
  EXPECT_EQ(refused.exitCode, 1);
  EXPECT_NE(refused.err.find("--in-place"), std::string::npos) << refused.err;
  EXPECT_EQ(readFile(in), before);

  const CommandResult valve = brushtrace("convert '" + in.string() + "' -o '" + (dir / "v.map").string() + "' --dialect valve220");
  ASSERT_EQ(valve.exitCode, 0) << valve.err;
  EXPECT_NE(readFile(dir / "v.map").find("// Format: Valve\n"), std::string::npos);
  EXPECT_NE(readFile(dir / "v.map").find("[ 1 0 0 16 ] [ 0 -1 0 8 ]"), std::string::npos);

  const CommandResult inPlace = brushtrace("convert '" + in.string() + "' -o '" + in.string() + "' --in-place --dialect valve220");
  ASSERT_EQ(inPlace.exitCode, 0) << inPlace.err;
  EXPECT_EQ(readFile(in), readFile(dir / "v.map"));

  EXPECT_EQ(brushtrace("convert '" + in.string() + "' -o x.map --dialect quake5").exitCode, 2);
  std::filesystem::remove_all(dir);
}

} // namespace
