// Entity models as `brushtrace render` and `info` report them (README "Entity models"):
// maps/models/oa_items.map without a game install (nothing drawn, one line saying so, exit 0)
// and with OpenArena's (Debian openarena-085-data), where installed.
#include "tests/app/run_command.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using bt::test::brushtrace;

const std::string kLevel = "'" + (bt::test::mapsDir() / "models" / "oa_items.map").string() + "'";
const fs::path kOpenArena = "/usr/share/games/openarena";

fs::path output(const std::string& name) {
  return fs::temp_directory_path() / ("bt_entity_models_" + name + "_" + std::to_string(::getpid()) + ".png");
}

TEST(EntityModelsCommand, WithoutTheGameTheLevelRendersAndOneLineSaysWhatWasNotDrawn) {
  const fs::path png = output("none");
  const auto r = brushtrace("render " + kLevel + " --backend cpu --size 32x24 --spp 1 -o '" + png.string() + "'");
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("2 entity models not drawn: no game install holds them (--game, --basedir; "
                       "models/powerups/health/medium_cross.md3, models/weapons2/rocketl/rocketl.md3)\n"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("entity models 2"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::is_regular_file(png));
  fs::remove(png);
}

TEST(EntityModelsCommand, WithOpenArenaTheItemsAreDrawnAndCounted) {
  if (!fs::is_directory(kOpenArena / "baseoa")) GTEST_SKIP() << kOpenArena << "/baseoa not installed (Debian openarena-085-data)";
  const std::string game = " --game quake3 --basedir " + kOpenArena.string();
  const fs::path png = output("oa");
  const auto r = brushtrace("render " + kLevel + game + " --backend cpu --size 32x24 --spp 1 -o '" + png.string() + "'");
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find(", entity models 2 ("), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("not drawn"), std::string::npos) << r.out;
  fs::remove(png);
  const auto info = brushtrace("info " + kLevel + game + " --json");
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const nlohmann::json json = nlohmann::json::parse(info.out);
  EXPECT_EQ(json["models"], 2);
  EXPECT_GT(json["model_triangles"].get<int>(), 100);
}

} // namespace
