// `brushtrace render` as users run it: the built executable, on the default map and on bad
// input. The tracers themselves are tested in tests/render and tests/gl; this is the command's
// contract (README): its default map, the camera line, the progress lines, the outputs, the
// backend choice, the errors, and that a failed render leaves existing files alone.
#include "tests/app/run_command.h"
#include "tests/test_data.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

using bt::test::brushtrace;
using bt::test::CommandResult;
namespace fs = std::filesystem;
constexpr auto npos = std::string::npos;

// A folder of its own for one test's files.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name)
      : path(fs::temp_directory_path() / ("bt_render_cmd_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::vector<std::string> files() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(path)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
};

std::string quoted(const fs::path& p) {
  return "'" + p.string() + "'";
}

struct ReadImage {
  int width = 0, height = 0;
  std::vector<std::string> channels;
  double mean = 0.0; // over every channel and pixel
};

std::optional<ReadImage> readImage(const fs::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return std::nullopt;
  const OIIO::ImageSpec& spec = in->spec();
  ReadImage image{spec.width, spec.height, spec.channelnames, 0.0};
  std::vector<float> pixels(size_t(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())) return std::nullopt;
  for (float v : pixels) image.mean += v;
  image.mean /= double(std::max<size_t>(pixels.size(), 1));
  return image;
}

// Every channel of every pixel, as floats 0..1 (8-bit PNG values / 255).
std::vector<float> readPixels(const fs::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<float> pixels(size_t(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())) return {};
  return pixels;
}

const char* kSmall = " --size 64x36 --spp 2";

TEST(RenderCommand, RendersTheDefaultMapToPngAndExrOnTheCpu) {
  TempDir dir("cpu");
  const CommandResult png = brushtrace("render -o " + quoted(dir.path / "start.png") + kSmall + " --backend cpu");
  ASSERT_EQ(png.exitCode, 0) << png.err;
  // The camera it used, in the form --camera takes, and where it came from: maps/start.map's
  // info_intermission.
  const std::regex cameraLine(R"(camera \(-?[0-9.]+ -?[0-9.]+ -?[0-9.]+\) -?[0-9.]+ -?[0-9.]+ -?[0-9.]+ \(info_intermission\)\n)");
  EXPECT_TRUE(std::regex_search(png.out, cameraLine)) << png.out;
  EXPECT_NE(png.out.find("wrote " + (dir.path / "start.png").string() + " (64x36, 2 spp, faithful lighting, cpu)"), npos) << png.out;
  const std::optional<ReadImage> tonemapped = readImage(dir.path / "start.png");
  ASSERT_TRUE(tonemapped);
  EXPECT_EQ(tonemapped->width, 64);
  EXPECT_EQ(tonemapped->height, 36);
  EXPECT_GT(tonemapped->mean, 0.05); // a lit level, not a black image

  const CommandResult exr = brushtrace("render -o " + quoted(dir.path / "start.exr") + kSmall + " --backend cpu --quiet");
  ASSERT_EQ(exr.exitCode, 0) << exr.err;
  const std::optional<ReadImage> linear = readImage(dir.path / "start.exr");
  ASSERT_TRUE(linear);
  // Beauty, the AOV layers and the second moment of the samples' luminance, which lets a stored
  // image be denoised again (OpenEXR stores a file's channels sorted, so compared as a set).
  std::vector<std::string> channels = linear->channels;
  std::sort(channels.begin(), channels.end());
  EXPECT_EQ(channels,
            (std::vector<std::string>{"B", "G", "R", "albedo.B", "albedo.G", "albedo.R", "depth.Z", "moment2.Y", "normal.X", "normal.Y",
                                      "normal.Z"}));
  // Written under a temporary name and renamed: nothing else is left beside the outputs.
  EXPECT_EQ(dir.files(), (std::vector<std::string>{"start.exr", "start.png"}));
}

TEST(RenderCommand, PrintsPlainProgressLinesWhenNotOnATerminalAndNothingWhenQuiet) {
  TempDir dir("progress");
  const CommandResult r = brushtrace("render -o " + quoted(dir.path / "a.png") + kSmall + " --backend cpu");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("[100%] spp 2/2 est 00:00:00\n"), npos) << r.out;
  EXPECT_EQ(r.out.find('\r'), npos) << "no carriage returns without a terminal";
  const CommandResult quiet = brushtrace("render -o " + quoted(dir.path / "b.png") + kSmall + " --backend cpu --quiet");
  ASSERT_EQ(quiet.exitCode, 0) << quiet.err;
  EXPECT_EQ(quiet.out, "");
}

TEST(RenderCommand, TakesTheCameraItWasGiven) {
  TempDir dir("camera");
  const CommandResult r = brushtrace("render -o " + quoted(dir.path / "a.png") + kSmall + " --backend cpu --camera '(0 0 64) 10 90 0'");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("camera (0 0 64) 10 90 0 (--camera)\n"), npos) << r.out;
  const CommandResult bad = brushtrace("render -o " + quoted(dir.path / "b.png") + kSmall + " --backend cpu --camera '0 0 64'");
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("--camera: expected \"(x y z) pitch yaw roll\""), npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir.path / "b.png"));
}

// Every way a render cannot go on once it has started: a message naming the file (and line and
// column where there is one), exit 1, and the output left as it was. (What the options alone
// show wrong is a usage error, exit 2, before the work: usage_errors_test.cpp.)
TEST(RenderCommand, BadInputFailsWithAMessageAndLeavesTheOutputAlone) {
  TempDir dir("bad");
  const fs::path out = dir.path / "keep.png";
  std::ofstream(out) << "an earlier render";
  auto unchanged = [&] {
    std::ifstream in(out);
    return std::string(std::istreambuf_iterator<char>(in), {}) == "an earlier render";
  };

  const fs::path malformed = dir.path / "bad.map";
  std::ofstream(malformed) << "{\n\"classname\" \"worldspawn\"\n{\n( 0 0 0 ) ( 0 1 0 ) ( 1 0 0 ) a 0 zero 0 1 1\n}\n}\n";
  const CommandResult r = brushtrace("render " + quoted(malformed) + " -o " + quoted(out) + kSmall + " --backend cpu");
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find(malformed.string() + ":4:35: error: bad number 'zero'"), npos) << r.err;
  EXPECT_TRUE(unchanged());
  EXPECT_EQ(dir.files(), (std::vector<std::string>{"bad.map", "keep.png"}));
}

// A level with nothing to draw (an empty .map, or only clip brushes) would render black, which
// looks like a lighting bug: it warns and fails, and writes nothing.
TEST(RenderCommand, ALevelWithNoDrawnFaceWarnsAndExitsOne) {
  TempDir dir("empty");
  const fs::path empty = dir.path / "empty.map";
  std::ofstream(empty) << "{\n\"classname\" \"worldspawn\"\n}\n";
  const fs::path clip = dir.path / "clip.map";
  std::ofstream(clip) << "{\n\"classname\" \"worldspawn\"\n{\n" // maps/dialects/standard.map's floor, as clip
                         "( -256 -256 -16 ) ( -256 256 -16 ) ( -256 -256 0 ) clip 0 0 0 1 1\n"
                         "( -256 -256 -16 ) ( -256 -256 0 ) ( 256 -256 -16 ) clip 0 0 0 1 1\n"
                         "( -256 -256 -16 ) ( 256 -256 -16 ) ( -256 256 -16 ) clip 0 0 0 1 1\n"
                         "( 256 256 0 ) ( 256 -256 0 ) ( -256 256 0 ) clip 0 0 0 1 1\n"
                         "( 256 256 0 ) ( -256 256 0 ) ( 256 256 -16 ) clip 0 0 0 1 1\n"
                         "( 256 256 0 ) ( 256 256 -16 ) ( 256 -256 0 ) clip 0 0 0 1 1\n}\n}\n";
  for (const fs::path& level : {empty, clip}) {
    SCOPED_TRACE(level.string());
    const CommandResult r = brushtrace("render " + quoted(level) + " -o " + quoted(dir.path / "out.png") + kSmall + " --backend cpu");
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_NE(r.err.find(level.string() + ": warning: the level has no face to draw; no image written"), npos) << r.err;
    EXPECT_FALSE(fs::exists(dir.path / "out.png"));
  }
  // The clip brush is drawn with --show-hidden, so that level renders.
  const CommandResult shown =
      brushtrace("render " + quoted(clip) + " -o " + quoted(dir.path / "out.png") + kSmall + " --backend cpu --show-hidden");
  EXPECT_EQ(shown.exitCode, 0) << shown.err;
}

// A brush of `texture` from (x0, y0, z0) to (x1, y1, z1), as a .map writes it.
std::string boxBrush(int x0, int y0, int z0, int x1, int y1, int z1, const std::string& texture) {
  const auto side = [&](int ax, int ay, int az, int bx, int by, int bz, int cx, int cy, int cz) {
    return fmt::format("( {} {} {} ) ( {} {} {} ) ( {} {} {} ) {} 0 0 0 1 1\n", ax, ay, az, bx, by, bz, cx, cy, cz, texture);
  };
  return "{\n" + side(x0, y0, z0, x0, y1, z0, x0, y0, z1) + side(x0, y0, z0, x0, y0, z1, x1, y0, z0) +
      side(x0, y0, z0, x1, y0, z0, x0, y1, z0) + side(x1, y1, z1, x1, y0, z1, x0, y1, z1) + side(x1, y1, z1, x0, y1, z1, x1, y1, z0) +
      side(x1, y1, z1, x1, y1, z0, x1, y0, z1) + "}\n";
}

// A key the compiler reads and faithful mode does not model is named in one warning line each
// (issue 14), at the first entity asking for it, with how many do; a key at its default ("0")
// asks for nothing. The shadow keys of the oracle's q1_light_switchableshadow_* and
// q1_lightignore levels, as a user renders such a level.
TEST(RenderCommand, EachKeyFaithfulModeDoesNotModelIsNamedInOneWarning) {
  TempDir dir("keys");
  const fs::path level = dir.path / "keys.map";
  std::ofstream(level) << "{\n\"classname\" \"worldspawn\"\n"
                       << boxBrush(-256, -256, -16, 256, 256, 0, "floor") << "}\n"
                       << "{\n\"classname\" \"light\"\n\"origin\" \"0 0 128\"\n}\n"
                       << "{\n\"classname\" \"light\"\n\"origin\" \"64 0 128\"\n\"targetname\" \"bars\"\n\"spawnflags\" \"1\"\n"
                          "\"_switchableshadow_target\" \"door1\"\n}\n"
                       << "{\n\"classname\" \"func_door\"\n\"targetname\" \"door1\"\n\"_switchableshadow\" \"1\"\n"
                       << boxBrush(-32, -32, 0, 32, 32, 64, "door") << "}\n"
                       << "{\n\"classname\" \"func_wall\"\n\"_lightignore\" \"1\"\n"
                       << boxBrush(96, -32, 0, 128, 32, 64, "wall") << "}\n"
                       << "{\n\"classname\" \"func_detail\"\n\"_lightignore\" \"1\"\n\"_phong\" \"0\"\n"
                       << boxBrush(-128, -32, 0, -96, 32, 64, "wall") << "}\n";
  const CommandResult r = brushtrace("render " + quoted(level) + " -o " + quoted(dir.path / "out.png") + kSmall + " --backend cpu");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  std::vector<std::string> named;
  std::istringstream lines(r.err);
  for (std::string line; std::getline(lines, line);)
    if (line.find(": warning: ") != npos && line.find("not modelled") != npos) named.push_back(line);
  const std::string at = level.string() + ":";
  EXPECT_EQ(named,
            (std::vector<std::string>{
                at +
                    "36: warning: func_wall: _lightignore: ignoring the lights is not modelled (2 brush entities); their faces "
                    "take every light, where the compiler gives them minlight only",
                at +
                    "23: warning: func_door: _switchableshadow: switchable shadows are not modelled (1 brush entity); without "
                    "`_shadow 1` they cast none, where the compiler's style 0 has their shadow and a style of their own the "
                    "light they block",
                at +
                    "16: warning: light: _switchableshadow_target: the shadow a light's style switches is not modelled (1 "
                    "light); they light as any other, where the compiler's give no light of their own (`_nostaticlight`)",
            }))
      << r.err;
}

// --lighting compiled draws a .bsp's own lightmaps (tests/render/compiled_view_test.cpp checks
// the pixels); a level without any says so in one line and renders faithful light; a compiled
// Quake 3 level renders compiled unless told otherwise, with a note.
TEST(RenderCommand, CompiledLightingShowsTheLightmapsOrSaysWhyNot) {
  BT_REQUIRE_SHARED(shared);
  TempDir dir("compiled");
  const std::string out = " -o " + quoted(dir.path / "out.png") + kSmall + " --backend cpu";
  const fs::path lit = shared / "oracle/lit/maps_quake_map_source_e1m1.bsp";
  const CommandResult shown = brushtrace("render " + quoted(lit) + out + " --lighting compiled");
  EXPECT_EQ(shown.exitCode, 0) << shown.err;
  EXPECT_NE(shown.out.find("compiled lighting"), npos) << shown.out;
  EXPECT_EQ(shown.err.find("showing faithful lighting"), npos) << shown.err;

  const fs::path unlit = shared / "oracle/maps_ericw-tools_testmaps_q1_cube.bsp";
  const CommandResult fallback = brushtrace("render " + quoted(unlit) + out + " --lighting compiled");
  EXPECT_EQ(fallback.exitCode, 0) << fallback.err;
  EXPECT_NE(fallback.err.find(unlit.string() +
                              ": warning: the level has no lightmaps (compiled without light); showing faithful "
                              "lighting"),
            npos)
      << fallback.err;
  EXPECT_NE(fallback.out.find("faithful lighting"), npos) << fallback.out;
  EXPECT_TRUE(fs::exists(dir.path / "out.png"));

  const fs::path openArena = "/usr/share/games/openarena/baseoa/pak1-maps.pk3";
  if (!fs::exists(openArena)) GTEST_SKIP() << openArena << " not found: the Quake 3 default is not checked";
  const fs::path level = openArena.string() + ":maps/aggressor.bsp";
  const CommandResult quake3 = brushtrace("render " + quoted(level) + out + " --no-textures");
  EXPECT_EQ(quake3.exitCode, 0) << quake3.err;
  EXPECT_NE(quake3.err.find("note: a compiled Quake 3 level keeps no lights; showing its lightmaps (--lighting compiled)"), npos)
      << quake3.err;
  EXPECT_NE(quake3.out.find("compiled lighting"), npos) << quake3.out;
  const CommandResult told = brushtrace("render " + quoted(level) + out + " --no-textures --lighting faithful");
  EXPECT_EQ(told.err.find("note: a compiled Quake 3"), npos) << told.err;
  EXPECT_NE(told.out.find("faithful lighting"), npos) << told.out;
}

// --lighting difference: each pixel of its PNG is the heat colour of the largest channel
// difference between the compiled and the faithful PNGs of the same view (README's scale: 0
// black, 8 steps blue, 16 green, 24 yellow, 32 or more red, linear between).
TEST(RenderCommand, DifferenceIsTheHeatMapOfCompiledAgainstFaithful) {
  BT_REQUIRE_SHARED(shared);
  TempDir dir("difference");
  const fs::path level = shared / "oracle/lit/maps_ericw-tools_testmaps_q1_light_suntexture.bsp";
  const std::string common = " --size 96x60 --spp 1 --backend cpu --quiet";
  for (const char* mode : {"faithful", "compiled", "difference"}) {
    const CommandResult r =
        brushtrace("render " + quoted(level) + " -o " + quoted(dir.path / (std::string(mode) + ".png")) + common + " --lighting " + mode);
    ASSERT_EQ(r.exitCode, 0) << mode << ": " << r.err;
  }
  const std::vector<float> faithful = readPixels(dir.path / "faithful.png"), compiled = readPixels(dir.path / "compiled.png"),
                           difference = readPixels(dir.path / "difference.png");
  ASSERT_EQ(faithful.size(), size_t(96 * 60 * 3));
  ASSERT_EQ(compiled.size(), faithful.size());
  ASSERT_EQ(difference.size(), faithful.size());
  const auto heat = [](int steps) {
    const float stops[5][3] = {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
    const float at = float(std::min(steps, 32)) / 8.0f;
    const int i = std::min(int(at), 3);
    const float w = at - float(i);
    return std::array<float, 3>{stops[i][0] * (1 - w) + stops[i + 1][0] * w, stops[i][1] * (1 - w) + stops[i + 1][1] * w,
                                stops[i][2] * (1 - w) + stops[i + 1][2] * w};
  };
  size_t differing = 0, off = 0;
  for (size_t p = 0; p < faithful.size() / 3; ++p) {
    int steps = 0;
    for (size_t c = 0; c < 3; ++c) steps = std::max(steps, int(std::lround(std::abs(faithful[p * 3 + c] - compiled[p * 3 + c]) * 255.0f)));
    differing += steps > 0;
    const std::array<float, 3> want = heat(steps);
    for (size_t c = 0; c < 3; ++c) off += std::abs(difference[p * 3 + c] - want[c]) > 1.0f / 255.0f + 1e-4f;
  }
  EXPECT_EQ(off, 0u);
  EXPECT_GT(differing, 100u) << "the two modes must disagree somewhere for the test to show anything";
}

// Every form --camera takes puts the camera at the same place: the same pixels as the
// parenthesised form (albedo: one sample through each pixel centre, so the images compare
// exactly), and the camera line printed in that form.
TEST(RenderCommand, CameraTakesQuakeSetposFormsAndNoRoll) {
  TempDir dir("setpos");
  const std::string args = " --size 64x36 --aov albedo --backend cpu";
  const CommandResult reference = brushtrace("render -o " + quoted(dir.path / "ref.png") + args + " --camera '(-100 50 64) 10 30 0'");
  ASSERT_EQ(reference.exitCode, 0) << reference.err;
  const std::vector<float> expected = readPixels(dir.path / "ref.png");
  ASSERT_EQ(expected.size(), size_t(64 * 36 * 3));
  const std::vector<std::string> forms{"setpos -100 50 64 10 30 0", "setpos -100 50 64 10 30", "(-100 50 64) 10 30",
                                       "setpos -100 50 64;setang 10 30 0", "setpos -100.0 50.0 64.0; setang 10.0 30.0"};
  for (size_t i = 0; i < forms.size(); ++i) {
    SCOPED_TRACE(forms[i]);
    const fs::path out = dir.path / ("form" + std::to_string(i) + ".png");
    const CommandResult r = brushtrace("render -o " + quoted(out) + args + " --camera '" + forms[i] + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("camera (-100 50 64) 10 30 0 (--camera)\n"), npos) << r.out;
    EXPECT_EQ(readPixels(out), expected);
  }
  for (const std::string bad : {"setpos 1 2 3", "setpos 1 2 3 4 5 6 7", "setpos 1 2 3;setang", "(1 2) 3 4 5", "setpos 1 2 x 4 5"}) {
    const CommandResult r = brushtrace("render -o " + quoted(dir.path / "bad.png") + args + " --camera '" + bad + "'");
    EXPECT_EQ(r.exitCode, 2) << bad;
    EXPECT_NE(r.err.find("--camera"), npos) << r.err;
  }
}

// The last progress line says 100 %, whichever of --spp and --time ends the render: the
// fraction is that of the limit that ends it.
TEST(RenderCommand, ProgressReachesOneHundredPercentWithTimeAndSpp) {
  TempDir dir("limits");
  const std::string base = "render -o " + quoted(dir.path / "a.png") + " --size 32x18 --backend cpu";
  const std::regex last(R"(\[100%\] spp ([0-9]+)/([0-9?]+) est 00:00:00\nwrote )");
  std::smatch m;
  const CommandResult byTime = brushtrace(base + " --spp 1000000 --time 1");
  ASSERT_EQ(byTime.exitCode, 0) << byTime.err;
  ASSERT_TRUE(std::regex_search(byTime.out, m, last)) << byTime.out;
  EXPECT_EQ(m[2], "1000000");
  EXPECT_NE(byTime.out.find("wrote " + (dir.path / "a.png").string() + " (32x18, " + m[1].str() + " spp"), npos) << byTime.out;

  const CommandResult bySpp = brushtrace(base + " --spp 3 --time 600");
  ASSERT_EQ(bySpp.exitCode, 0) << bySpp.err;
  EXPECT_NE(bySpp.out.find("[100%] spp 3/3 est 00:00:00\n"), npos) << bySpp.out;

  // --time alone: as many samples as fit, not the default --spp.
  const CommandResult timeAlone = brushtrace(base + " --time 1");
  ASSERT_EQ(timeAlone.exitCode, 0) << timeAlone.err;
  ASSERT_TRUE(std::regex_search(timeAlone.out, m, last)) << timeAlone.out;
  EXPECT_EQ(m[2], "?");
  EXPECT_GT(std::stoi(m[1]), 64) << timeAlone.out;
}

// Through a pipe, each progress line arrives when it is printed, not in one block when the
// render ends: the first one is read while the render still has a second and a half to go.
TEST(RenderCommand, ProgressLinesArriveThroughAPipeWhileRendering) {
  TempDir dir("pipe");
  const std::string command = "'" + (bt::test::binaryDir() / "brushtrace").string() + "' render -o " + quoted(dir.path / "a.png") +
      " --size 32x18 --backend cpu --time 3 2>/dev/null";
  FILE* pipe = ::popen(command.c_str(), "r");
  ASSERT_TRUE(pipe);
  using Clock = std::chrono::steady_clock;
  std::optional<Clock::time_point> firstProgress;
  std::string firstLine;
  char line[512];
  while (std::fgets(line, sizeof line, pipe)) {
    if (firstLine.empty()) firstLine = line;
    if (!firstProgress && line[0] == '[') firstProgress = Clock::now();
  }
  const Clock::time_point end = Clock::now();
  EXPECT_EQ(::pclose(pipe), 0);
  EXPECT_EQ(firstLine.rfind("camera (", 0), 0u) << firstLine;
  ASSERT_TRUE(firstProgress) << "no progress line";
  EXPECT_GT(std::chrono::duration<double>(end - *firstProgress).count(), 1.5);
}

// --backend gl renders on the GL tracer where a GL 4.5 context can be made (Mesa's llvmpipe
// here and in CI), else says in one line why and renders on the CPU; auto passes over a
// software GL, saying so.
TEST(RenderCommand, GlBackendUsesGlWhereItCanAndSaysWhyNotElsewhere) {
  TempDir dir("gl");
  const CommandResult gl = brushtrace("render -o " + quoted(dir.path / "gl.png") + kSmall + " --backend gl");
  ASSERT_EQ(gl.exitCode, 0) << gl.err;
  ASSERT_TRUE(readImage(dir.path / "gl.png"));
  // Without a GL 4.5 context the contract is the fallback: one line saying why, then the CPU.
  if (gl.err.find("brushtrace: no GL 4.5 context (") != npos) {
    EXPECT_NE(gl.out.find("faithful lighting, cpu)"), npos) << gl.out;
    return;
  }
  EXPECT_NE(gl.out.find("faithful lighting, gl "), npos) << gl.out;
  if (gl.out.find("llvmpipe") == npos) return; // a hardware GL: auto would use it too
  const CommandResult autoBackend = brushtrace("render -o " + quoted(dir.path / "auto.png") + kSmall);
  ASSERT_EQ(autoBackend.exitCode, 0) << autoBackend.err;
  EXPECT_NE(autoBackend.err.find("brushtrace: GL context is software (llvmpipe"), npos) << autoBackend.err;
  EXPECT_NE(autoBackend.out.find("faithful lighting, cpu)"), npos) << autoBackend.out;
}

// An AOV to a PNG through --backend gl renders the AOVs alone (no path tracer: on llvmpipe its
// build was most of the time) and draws what the CPU reference draws: the PNGs of both backends
// agree pixel for pixel up to one 8-bit step (bilinear texels and depth's scale from float
// rounding), but for the odd silhouette pixel that sees the other face.
TEST(RenderCommand, AovPngOnTheGlBackendEqualsTheCpus) {
  TempDir dir("aov");
  for (const std::string aov : {"albedo", "normal", "depth", "face"}) {
    SCOPED_TRACE(aov);
    const std::string args = " --size 64x36 --aov " + aov;
    const CommandResult gl = brushtrace("render -o " + quoted(dir.path / (aov + "-gl.png")) + args + " --backend gl");
    ASSERT_EQ(gl.exitCode, 0) << gl.err;
    if (gl.err.find("brushtrace: no GL 4.5 context (") != npos) { // the fallback, tested above
      EXPECT_NE(gl.out.find("--aov " + aov + ", cpu)"), npos) << gl.out;
      continue;
    }
    EXPECT_NE(gl.out.find("(64x36, --aov " + aov + ", gl "), npos) << gl.out;
    const CommandResult cpu = brushtrace("render -o " + quoted(dir.path / (aov + "-cpu.png")) + args + " --backend cpu --quiet");
    ASSERT_EQ(cpu.exitCode, 0) << cpu.err;
    const std::vector<float> glPixels = readPixels(dir.path / (aov + "-gl.png"));
    const std::vector<float> cpuPixels = readPixels(dir.path / (aov + "-cpu.png"));
    ASSERT_EQ(glPixels.size(), size_t(64 * 36 * 3));
    ASSERT_EQ(glPixels.size(), cpuPixels.size());
    size_t differing = 0, lit = 0;
    for (size_t p = 0; p < cpuPixels.size(); p += 3) {
      float difference = 0.0f;
      for (size_t c = 0; c < 3; ++c) difference = std::max(difference, std::abs(glPixels[p + c] - cpuPixels[p + c]));
      differing += difference > 1.5f / 255.0f;
      lit += cpuPixels[p] + cpuPixels[p + 1] + cpuPixels[p + 2] > 0.0f;
    }
    EXPECT_LE(differing, cpuPixels.size() / 3 / 100) << differing << " pixels differ by more than one step";
    EXPECT_GT(lit, cpuPixels.size() / 3 / 2) << "most of the view sees the level";
  }
}

} // namespace
