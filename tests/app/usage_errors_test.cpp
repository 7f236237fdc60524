// Usage errors of the GL commands through the executable: a bad --gl-textures exits 2 like every
// other usage error (README), naming the flag, and asking bindless of a context without it says
// which flag asked.
#include "tests/app/run_command.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <unistd.h>

namespace {

using bt::test::brushtrace;
using bt::test::CommandResult;
constexpr auto npos = std::string::npos;

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
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("bt_usage_bindless_" + std::to_string(::getpid()) + ".png");
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
