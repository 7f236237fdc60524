// Usage errors through the executable (README, "Command line"): exit 2 and a message naming the
// option, found from the options alone before any work starts; and the commands listed when
// none, or a mistyped one, is given.
#include "tests/app/run_command.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <vector>
#include <string>
#include <unistd.h>

namespace {

using bt::test::brushtrace;
using bt::test::CommandResult;
constexpr auto npos = std::string::npos;
namespace fs = std::filesystem;

std::string quoted(const fs::path& p) {
  return "'" + p.string() + "'";
}

const char* kCommands[] = {"info", "dump", "convert", "render", "view", "bench"};

TEST(UsageErrors, BrushtraceAloneListsTheCommands) {
  const CommandResult r = brushtrace("");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("brushtrace: a command is required\ncommands:\n"), npos) << r.err;
  for (const char* command : kCommands) EXPECT_NE(r.err.find("\n  " + std::string(command) + " "), npos) << command << "\n" << r.err;
}

TEST(UsageErrors, AMistypedCommandListsTheCommandsAndSuggestsANearMiss) {
  const CommandResult near = brushtrace("rendr -o x.png");
  EXPECT_EQ(near.exitCode, 2);
  EXPECT_NE(near.err.find("brushtrace: unknown command 'rendr'; did you mean 'render'?\ncommands:\n"), npos) << near.err;
  EXPECT_NE(near.err.find("\n  convert "), npos) << near.err;
  const CommandResult swapped = brushtrace("covnert a.map -o b.map");
  EXPECT_NE(swapped.err.find("did you mean 'convert'?"), npos) << swapped.err;
  const CommandResult far = brushtrace("frobnicate");
  EXPECT_EQ(far.exitCode, 2);
  EXPECT_NE(far.err.find("brushtrace: unknown command 'frobnicate'\ncommands:\n"), npos) << far.err;
  EXPECT_EQ(brushtrace("--help").exitCode, 0);
}

// Each bad option exits 2 with its name in the message, and is found before the work starts:
// the level is malformed, so a check made after the import would exit 1 with the level's error
// instead. Nothing is written.
TEST(UsageErrors, EveryCommandChecksItsOptionsBeforeAnyWork) {
  const fs::path dir = fs::temp_directory_path() / ("bt_usage_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "locked");
  const std::string level = quoted(dir / "bad.map");
  std::ofstream(dir / "bad.map") << "{\n\"classname\" \"worldspawn\"\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a 0 zero 0 1 1\n}\n}\n";
  // A folder no file can be made in. Root writes through permission bits, so as root /proc.
  fs::permissions(dir / "locked", fs::perms::owner_read | fs::perms::owner_exec);
  const fs::path locked = ::geteuid() == 0 ? fs::path("/proc") : dir / "locked";
  const std::string out = " -o " + quoted(dir / "out.png");
  const std::vector<std::pair<std::string, std::string>> cases{
      {"render " + level + " -o " + quoted(dir / "out.jpg"), "--output: '" + (dir / "out.jpg").string() + "': output must be .png or .exr"},
      {"render " + level + " -o " + quoted(dir / "missing" / "out.png"),
       "--output: folder '" + (dir / "missing").string() + "' does not exist"},
      {"render " + level + " -o " + quoted(locked / "out.png"), "--output: folder '" + locked.string() + "' is not writable"},
      {"render " + level + out + " --spp 0", "--spp"},
      {"render " + level + out + " --spp -3", "--spp"},
      {"render " + level + out + " --time 0", "--time"},
      {"render " + level + out + " --camera '0 0 64'", "--camera: expected"},
      {"render " + level + out + " --size 0x10", "--size"},
      {"render " + quoted(dir / "missing.map") + out, "map: '" + (dir / "missing.map").string() + "': no such file"},
      {"render " + quoted(dir) + out, "is a folder, not a level file"},
      {"render " + level + out + " --wad " + quoted(dir / "missing.wad"), "--wad"},
      {"render " + level + out + " --palette " + quoted(dir / "missing.lmp"), "--palette"},
      {"render " + level + out + " --textures " + quoted(dir / "missing"), "--textures"},
      {"render " + level + out + " --bounces -1", "--bounces"},
      {"render " + level + out + " --clamp-indirect -1", "--clamp-indirect"},
      {"render " + level + out + " --threads -1", "--threads"},
      {"render " + level + out + " --style 0=1", "--style"},
      {"render " + level + out + " --style 5=3", "--style"},
      {"render " + level + out + " --style 5", "--style"},
      {"info " + quoted(dir / "missing.map"), "MAP: '"},
      {"dump " + quoted(dir / "missing.map"), "MAP: '"},
      {"convert " + quoted(dir / "missing.map") + " -o " + quoted(dir / "out.map"), "IN: '"},
      {"convert " + level + " -o " + quoted(dir / "missing" / "out.map"), "--output: folder"},
      {"convert " + level + " -o " + quoted(locked / "out.map"), "--output: folder"},
      {"view " + level + " --camera 'setpos 1 2'", "--camera: expected"},
      {"view " + level + " --screenshots " + quoted(dir / "missing"), "--screenshots: folder"},
      {"view " + level + " --bounces 65", "--bounces"},
      {"view " + level + " --clamp-indirect near", "--clamp-indirect"},
      {"view " + level + " --backend vulkan", "--backend"},
      {"view " + quoted(dir / "missing.map"), "map: '"},
      {"bench " + quoted(dir / "missing.map"), "map: '"},
      {"bench " + level + " --seconds 0", "--seconds"},
      {"bench " + level + " --clamp-indirect 5000", "--clamp-indirect"},
  };
  for (const auto& [args, message] : cases) {
    const CommandResult r = brushtrace(args);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(message), npos) << args << "\nexpected: " << message << "\n" << r.err;
  }
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir)) files.push_back(e.path().filename().string());
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, (std::vector<std::string>{"bad.map", "locked"}));
  fs::permissions(dir / "locked", fs::perms::owner_all);
  fs::remove_all(dir);
}

TEST(UsageErrors, UnknownGlTexturePathExitsTwoInEveryCommand) {
  const std::string map = "'" + (bt::test::mapsDir() / "start.map").string() + "'";
  for (const std::string& command : {std::string("render -o unused.png"), "view " + map, "bench " + map}) {
    SCOPED_TRACE(command);
    const CommandResult r = brushtrace(command + " --gl-textures foo");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find("--gl-textures"), npos) << r.err;
    EXPECT_NE(r.err.find("foo"), npos) << r.err;
  }
}

// Where the GL context has no bindless textures (llvmpipe here and in CI), asking for them is an
// error naming --gl-textures, not a fallback; a GPU with bindless renders.
TEST(UsageErrors, BindlessWithoutTheExtensionNamesTheFlag) {
  const std::filesystem::path out = std::filesystem::temp_directory_path() / ("bt_usage_bindless_" + std::to_string(::getpid()) + ".png");
  const CommandResult r = brushtrace("render -o '" + out.string() + "' --size 16x9 --aov albedo --backend gl --gl-textures bindless");
  std::filesystem::remove(out);
  // Without a GL 4.5 context there is no texture path to ask about: the render falls back to the
  // CPU (RenderCommand.GlBackendUsesGlWhereItCanAndSaysWhyNotElsewhere checks that line) and succeeds.
  if (r.err.find("brushtrace: no GL 4.5 context (") != npos) {
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err.find("GL_ARB_bindless_texture"), npos) << r.err;
    return;
  }
  if (r.exitCode == 0) {
    EXPECT_EQ(r.err.find("GL_ARB_bindless_texture"), npos) << r.err;
    return; // the context has bindless textures
  }
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("--gl-textures bindless: "), npos) << r.err;
  EXPECT_NE(r.err.find("has no GL_ARB_bindless_texture"), npos) << r.err;
}

} // namespace
