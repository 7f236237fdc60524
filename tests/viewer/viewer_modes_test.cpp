// The view modes of keys 2, 3, 8 and 9 (viewer/view_modes.h) and physical mode's denoiser, every
// pixel of the window in colour against what each mode's rule gives for the test room, whose
// walls are all one texture of one colour: fullbright is that colour, light only is the picture of
// the same room with white walls, flat is render --aov face's colour of each face; the GL window
// and the CPU window show the same image.
#include "renderer/denoise.h"
#include "renderer/image_output.h"
#include "tests/app/run_command.h"
#include "tests/test_data.h"
#include "tests/viewer/viewer_test_fixture.h"
#include "tests/viewer/x_keys.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <array>
#include <set>

namespace bt {
namespace {

using namespace viewer_test;
using Rgb = std::array<uint8_t, 3>;

constexpr Rgb kOrange{200, 120, 60};
constexpr Rgb kWhite{255, 255, 255};

// A 16x16 texture of one colour, saved as an image editor saves it.
void paintWall(const fs::path& dir, Rgb rgb) {
  const fs::path png = dir / "textures/wall.png", temp = dir / "textures/saving-wall.png";
  std::vector<uint8_t> pixels(16 * 16 * 3);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = rgb[i % 3];
  auto out = OIIO::ImageOutput::create(temp.string());
  ASSERT_TRUE(out && out->open(temp.string(), OIIO::ImageSpec(16, 16, 3, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) && out->close());
  fs::rename(temp, png);
}

// The largest channel difference between two display images (256: sizes differ).
int worstBetween(const Viewer::DisplayImage& a, const Viewer::DisplayImage& b) {
  if (a.width != b.width || a.height != b.height || a.rgba.empty()) return 256;
  int worst = 0;
  for (size_t i = 0; i < a.rgba.size(); ++i)
    if (i % 4 != 3) worst = std::max(worst, std::abs(int(a.rgba[i]) - int(b.rgba[i])));
  return worst;
}

// How many pixels differ in any channel.
size_t pixelsApart(const Viewer::DisplayImage& a, const Viewer::DisplayImage& b) {
  if (a.width != b.width || a.height != b.height || a.rgba.empty()) return size_t(-1);
  size_t n = 0;
  for (size_t i = 0; i + 3 < a.rgba.size(); i += 4)
    n += a.rgba[i] != b.rgba[i] || a.rgba[i + 1] != b.rgba[i + 1] || a.rgba[i + 2] != b.rgba[i + 2];
  return n;
}

// ... between every pixel and one colour.
int worstAgainst(const Viewer::DisplayImage& shown, Rgb rgb) {
  if (shown.rgba.empty()) return 256;
  int worst = 0;
  for (size_t i = 0; i < shown.rgba.size(); ++i)
    if (i % 4 != 3) worst = std::max(worst, std::abs(int(shown.rgba[i]) - int(rgb[i % 4])));
  return worst;
}

// Display bytes as the window's RGBA8.
Viewer::DisplayImage asShown(int width, int height, const std::vector<uint8_t>& rgb) {
  Viewer::DisplayImage image{width, height, std::vector<uint8_t>(size_t(width) * height * 4, 255)};
  for (size_t i = 0; i < rgb.size() / 3; ++i) std::copy_n(&rgb[i * 3], 3, &image.rgba[i * 4]);
  return image;
}

class ViewerModesTest : public ViewerWindowTest {
protected:
  ViewerOptions optionsFor(ViewerBackend backend, int maxSamples) const {
    ViewerOptions o = options();
    o.backend = backend;
    o.maxSamples = maxSamples;
    return o;
  }

  // The window once the luxels are baked and every pixel has `spp` samples (the views that
  // trace; the others are drawn from the AOVs in one frame).
  static Viewer::DisplayImage settled(Viewer& viewer, int spp) {
    // (Physical light has no luxels: the CPU window does not bake them then.)
    const bool faithful = viewer.lighting() == LightingMode::Faithful;
    if (viewer.mode() == ViewMode::Beauty || viewer.mode() == ViewMode::LightOnly)
      EXPECT_TRUE(frameUntil(viewer, [&] { return (viewer.luxelsBaked() || !faithful) && viewer.samples() >= spp; })) << "no refinement";
    EXPECT_TRUE(viewer.frame());
    return viewer.displayed();
  }

  // The window once physical mode's exposure, which follows the image smoothly, has stopped
  // moving: the same bytes three frames running.
  static Viewer::DisplayImage steady(Viewer& viewer) {
    Viewer::DisplayImage last = viewer.displayed();
    int same = 0;
    EXPECT_TRUE(frameUntil(
        viewer,
        [&] {
          Viewer::DisplayImage now = viewer.displayed();
          same = now.rgba == last.rgba ? same + 1 : 0;
          last = std::move(now);
          return same == 3;
        },
        30.0))
        << "the exposure never settled";
    return last;
  }

  // `brushtrace render` of the viewer's level from its camera, read back as the window's bytes.
  Viewer::DisplayImage render(const Viewer& viewer, const ViewerOptions& o, const std::string& flags) {
    const fs::path png = dir_ / "render.png";
    const test::CommandResult r = test::brushtrace(fmt::format("render '{}' --camera '{}' --size {}x{} --quiet -o '{}' {}", o.map,
                                                               formatCameraPose(viewer.camera()), o.width, o.height, png.string(), flags));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    // Read past OpenImageIO's image cache: it keys files by name and modification second, so a
    // render.png rewritten within the second came back as the one before (CI saw it).
    std::vector<uint8_t> rgb(size_t(o.width) * o.height * 3);
    auto in = OIIO::ImageInput::open(png.string());
    EXPECT_TRUE(in && in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, rgb.data())) << png;
    return asShown(o.width, o.height, rgb);
  }
};

TEST_F(ViewerModesTest, KeysChooseTheViewModesAndTheDenoiser) {
  Viewer viewer(options());
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 1; }));
  const std::pair<KeySym, ViewMode> keys[] = {{XK_2, ViewMode::Fullbright},
                                              {XK_3, ViewMode::Normal},
                                              {XK_8, ViewMode::LightOnly},
                                              {XK_9, ViewMode::Flat},
                                              {XK_1, ViewMode::Beauty}};
  for (const auto& [key, mode] : keys) {
    tap(viewer, key);
    ASSERT_TRUE(viewer.frame());
    EXPECT_EQ(viewer.mode(), mode) << toString(mode);
  }
  EXPECT_TRUE(viewer.denoising()) << "the denoiser is on by default";
  tap(viewer, XK_n);
  ASSERT_TRUE(viewer.frame());
  EXPECT_FALSE(viewer.denoising()) << "N did not turn the denoiser off";
}

// r_fullbright 1: the texture as it is, unlit. Every wall is orange, so every pixel is.
TEST_F(ViewerModesTest, FullbrightShowsTheTexturesWithoutLight) {
  paintWall(dir_, kOrange);
  for (const ViewerBackend backend : {ViewerBackend::Gl, ViewerBackend::Cpu}) {
    Viewer viewer(optionsFor(backend, 2));
    viewer.setMode(ViewMode::Fullbright);
    EXPECT_EQ(worstAgainst(settled(viewer, 1), kOrange), 0) << (viewer.cpuTracer() ? "CPU window" : "GL window");
    EXPECT_EQ(largestDifference(viewer.screenshot(), viewer.displayed()), 0) << "the screenshot is not what is shown";
  }
}

// r_drawflat 1: each face in its own colour, the one render --aov face gives it.
TEST_F(ViewerModesTest, FlatShowsEachFaceInItsOwnColour) {
  for (const ViewerBackend backend : {ViewerBackend::Gl, ViewerBackend::Cpu}) {
    const ViewerOptions o = optionsFor(backend, 2);
    Viewer viewer(o);
    viewer.setMode(ViewMode::Flat);
    const Viewer::DisplayImage shown = settled(viewer, 1);
    EXPECT_EQ(worstBetween(shown, render(viewer, o, "--aov face --backend cpu")), 0) << (viewer.cpuTracer() ? "CPU window" : "GL window");
    std::set<std::array<uint8_t, 3>> colours;
    for (size_t i = 0; i < shown.rgba.size(); i += 4) colours.insert({shown.rgba[i], shown.rgba[i + 1], shown.rgba[i + 2]});
    EXPECT_GE(colours.size(), 4u) << "the back wall, floor, ceiling and side walls in view are not each their own colour";
    EXPECT_EQ(largestDifference(viewer.screenshot(), shown), 0) << "the screenshot is not what is shown";
  }
}

// r_lightmap 1: the light on a white surface. The orange room's light only is the white room's picture.
TEST_F(ViewerModesTest, LightOnlyShowsTheLightOnAWhiteSurface) {
  const int spp = 3;
  paintWall(dir_, kWhite);
  Viewer::DisplayImage white;
  {
    Viewer viewer(optionsFor(ViewerBackend::Gl, spp));
    white = settled(viewer, spp);
  }
  paintWall(dir_, kOrange);
  Viewer::DisplayImage lit;
  for (const ViewerBackend backend : {ViewerBackend::Gl, ViewerBackend::Cpu}) {
    const ViewerOptions o = optionsFor(backend, spp);
    Viewer viewer(o);
    lit = settled(viewer, spp);
    viewer.setMode(ViewMode::LightOnly);
    const Viewer::DisplayImage alone = settled(viewer, spp);
    EXPECT_LE(worstBetween(alone, white), 2) << (viewer.cpuTracer() ? "CPU window" : "GL window") << ": not the white room's picture";
    EXPECT_GT(worstBetween(lit, white), 40) << "the orange room looks white: the test cannot tell";
    EXPECT_EQ(largestDifference(viewer.screenshot(), alone), 0) << "the screenshot is not what is shown";
    if (viewer.cpuTracer()) {
      paintWall(dir_, kWhite); // render --backend cpu of the white room, to the byte
      // The division by the texture and the sRGB round trip: at most 1 level.
      EXPECT_LE(worstBetween(alone, render(viewer, o, fmt::format("--backend cpu --spp {}", spp))), 1);
    }
  }
}

// The GL window and the CPU window show the same image in every view mode.
TEST_F(ViewerModesTest, BothWindowsShowTheSameImageInEachMode) {
  paintWall(dir_, kOrange);
  const ViewMode modes[] = {ViewMode::Fullbright, ViewMode::Normal, ViewMode::Flat, ViewMode::LightOnly};
  std::vector<Viewer::DisplayImage> shown[2];
  for (const ViewerBackend backend : {ViewerBackend::Gl, ViewerBackend::Cpu}) {
    Viewer viewer(optionsFor(backend, 3)); // one window at a time: imgui has one context
    for (const ViewMode mode : modes) {
      viewer.setMode(mode);
      shown[backend == ViewerBackend::Cpu].push_back(settled(viewer, 3));
    }
  }
  for (size_t m = 0; m < std::size(modes); ++m)
    // Faithful light's GL and CPU luxels agree within 2 levels (BakesTheLuxelsThenShowsWhatRenderShows).
    EXPECT_LE(worstBetween(shown[0][m], shown[1][m]), modes[m] == ViewMode::LightOnly ? 2 : 0) << toString(modes[m]);
}

// The viewer's fade (renderer/denoise_fade.h) shortened to end at 64 spp, as it did before issue
// 18's session 20: the real one ends at 1024 spp, which llvmpipe's window would take minutes over.
constexpr DenoiseFade kShortFade{16, 64};

// Physical mode's young image is the denoiser's, the converged one the raw beauty: the CPU window
// against render --backend cpu with and without --denoise, to the byte. (The CPU window keeps
// exposure 0 in physical mode.)
TEST_F(ViewerModesTest, TheCpuWindowDenoisesAYoungPhysicalImageAndShowsAConvergedOneRaw) {
  for (const int spp : {1, kShortFade.goneAt}) {
    ViewerOptions o = optionsFor(ViewerBackend::Cpu, spp);
    o.denoiseFade = kShortFade;
    o.lighting = LightingMode::Physical;
    o.lightingGiven = true;
    Viewer viewer(o);
    const Viewer::DisplayImage shown = settled(viewer, spp);
    const std::string flags = fmt::format("--backend cpu --lighting physical --bounces {} --exposure 0 --spp {}", o.bounces, spp);
    const Viewer::DisplayImage raw = render(viewer, o, flags);
    if (spp == 1) {
      EXPECT_EQ(worstBetween(shown, render(viewer, o, flags + " --denoise")), 0) << "1 spp: not the denoiser's image";
      EXPECT_GT(worstBetween(shown, raw), 20) << "the denoised and raw images look alike: the test cannot tell";
      EXPECT_EQ(largestDifference(viewer.screenshot(), shown), 0) << "the screenshot is not what is shown";
      viewer.setDenoise(false);
      EXPECT_EQ(worstBetween(settled(viewer, spp), raw), 0) << "N: not the raw image";
    } else {
      EXPECT_EQ(worstBetween(shown, raw), 0) << spp << " spp: not the raw image";
    }
  }
}

// The GL window: at 1 spp what is shown is the denoiser's output of the raw image and its AOVs
// (a screenshot's EXR with the denoiser off holds both); where the fade ends, the raw image.
TEST_F(ViewerModesTest, TheGlWindowDenoisesAYoungPhysicalImageAndShowsAConvergedOneRaw) {
  ViewerOptions o = optionsFor(ViewerBackend::Gl, 1);
  o.lighting = LightingMode::Physical;
  o.lightingGiven = true;
  {
    Viewer viewer(o);
    const Viewer::DisplayImage denoised = settled(viewer, 1);
    EXPECT_EQ(largestDifference(viewer.screenshot(), denoised), 0) << "the screenshot is not what is shown";
    viewer.setDenoise(false);
    const Viewer::DisplayImage raw = settled(viewer, 1);
    fs::path exr = viewer.screenshot();
    exr.replace_extension(".exr");
    auto in = OIIO::ImageInput::open(exr.string()); // past the image cache, as render() reads
    // The beauty, its AOVs and the second moment of its luminance (moment2.Y).
    ASSERT_TRUE(in && in->spec().nchannels == 11) << exr;
    const int n = o.width * o.height;
    std::vector<float> px(size_t(n) * 11);
    ASSERT_TRUE(in->read_image(0, 0, 0, 11, OIIO::TypeDesc::FLOAT, px.data()));
    // OpenEXR keeps the layers' channels in its own order: each is found by name.
    const auto channel = [&](const char* name) { return in->spec().channelindex(name); };
    const int r = channel("R"), g = channel("G"), b = channel("B"), ar = channel("albedo.R"), ag = channel("albedo.G"),
              ab = channel("albedo.B"), nx = channel("normal.X"), ny = channel("normal.Y"), nz = channel("normal.Z"),
              z = channel("depth.Z");
    ASSERT_GE(std::min({r, g, b, ar, ag, ab, nx, ny, nz, z}), 0) << "the screenshot's EXR lacks a layer";
    RenderImage image; // beauty with the window's exposure applied: the ACES display of it at 0 EV
    image.width = o.width, image.height = o.height, image.samples = 1;
    for (int i = 0; i < n; ++i) {
      const float* p = &px[size_t(i) * 11];
      image.beauty.emplace_back(p[r], p[g], p[b]);
      image.albedo.emplace_back(p[ar], p[ag], p[ab]);
      image.normal.emplace_back(p[nx], p[ny], p[nz]);
      image.depth.push_back(p[z]);
      image.face.push_back(std::isfinite(p[z]) ? 1u : 0u);
    }
    image.beauty = denoise(image);
    OutputSettings aces;
    aces.tonemap = Tonemap::Aces;
    // The GLSL filter gives the C++ one's values within 1e-4 (GlDenoise.TheShaderGivesTheCpuFiltersImage).
    EXPECT_LE(worstBetween(denoised, asShown(o.width, o.height, displayPixels(image, aces))), 1) << "1 spp: not the denoiser's image";
    EXPECT_GT(worstBetween(denoised, raw), 20) << "the denoised and raw images look alike: the test cannot tell";
  }
  o.maxSamples = kShortFade.goneAt;
  o.denoiseFade = kShortFade;
  Viewer viewer(o);
  settled(viewer, kShortFade.goneAt);
  const Viewer::DisplayImage shown = steady(viewer);
  viewer.setDenoise(false);
  EXPECT_EQ(worstBetween(shown, steady(viewer)), 0) << kShortFade.goneAt << " spp: not the raw image";
}

} // namespace
} // namespace bt

namespace bt {
namespace {

using namespace viewer_test;

// A light of `style` (0: a switchable one, which the compiler gives style 32) at `origin`.
std::string styledLight(int style, const char* origin, int value) {
  const std::string key = style ? fmt::format("\"style\" \"{}\"", style) : std::string("\"targetname\" \"lamp\"");
  return fmt::format("{{\n\"classname\" \"light\"\n\"origin\" \"{}\"\n\"light\" \"{}\"\n{}\n}}\n", origin, value, key);
}

// The light-style sliders: a styled light's slider at 0 takes exactly that light away, every pixel
// of the room it lights: the CPU window then draws what render --backend cpu draws of the room
// without it. The luxels are re-summed (lightmap_bake.h sumStyles): no reload.
TEST_F(ViewerModesTest, AStyleSliderAtZeroTakesThatLightAway) {
  save(roomMap(300) + styledLight(5, "64 64 -96", 250));
  const ViewerOptions o = optionsFor(ViewerBackend::Cpu, 2);
  Viewer viewer(o);
  const Viewer::DisplayImage both = settled(viewer, 2);
  ASSERT_EQ(viewer.lightStyles(), std::vector<int>{5});
  EXPECT_EQ(viewer.styleScale(5), 1.0f) << "a style starts as faithful mode shows it";

  viewer.setStyleScale(5, 0.0f);
  const Viewer::DisplayImage without = settled(viewer, 2);
  EXPECT_EQ(viewer.reloads(), 0) << "the slider reloaded the level";
  save(roomMap(300)); // the room without the styled light, for render
  const Viewer::DisplayImage expected = render(viewer, o, "--backend cpu --spp 2");
  EXPECT_EQ(worstBetween(without, expected), 0) << "style 5 at 0 is not the room without its light";
  EXPECT_GT(worstBetween(both, expected), 20) << "the styled light changes nothing: the test cannot tell";
}

// Two sliders moved (style 5, and a switchable light's style 32) in the CPU window and in the GL
// window: the image, every pixel, is render's of the level with those styles scaled (--style,
// today's whole bake of the scaled lights), with no import and no bake, within kRestyleSeconds
// of the slider (the re-sum and its first two samples per pixel of the 96x64 window).
constexpr double kRestyleSeconds = 5.0;

class ViewerStyleSlidersTest : public ViewerModesTest, public ::testing::WithParamInterface<ViewerBackend> {};

TEST_P(ViewerStyleSlidersTest, SlidersReSumTheLuxelsWithoutAReload) {
  const bool cpu = GetParam() == ViewerBackend::Cpu;
  save(roomMap(300) + styledLight(5, "64 64 -96", 250) + styledLight(0, "-64 -64 -96", 200));
  const ViewerOptions o = optionsFor(GetParam(), 2);
  Viewer viewer(o);
  settled(viewer, 2);
  ASSERT_EQ(viewer.lightStyles(), (std::vector<int>{5, 32}));
  const int imports = viewer.imports(), bakes = viewer.bakes();
  ASSERT_EQ(imports, 1);
  ASSERT_EQ(bakes, 1);
  // The GL window's first converged picture of a styled level is the GPU's bake, as for any
  // level (the CPU's per-style sets take minutes on lq_e4m3 here); the sets serve the sliders.
  EXPECT_EQ(viewer.gpuBakes(), cpu ? 0 : 1);

  const auto start = std::chrono::steady_clock::now();
  viewer.setStyleScale(5, 0.5f);
  viewer.setStyleScale(32, 1.5f);
  const Viewer::DisplayImage shown = settled(viewer, 2);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s window: the moved sliders' image at 2 spp in %.3f s\n", cpu ? "CPU" : "GL", seconds);
  EXPECT_EQ(viewer.imports(), imports) << "the slider imported the level again";
  EXPECT_EQ(viewer.bakes(), bakes) << "the slider baked the luxels again";
  EXPECT_EQ(viewer.reloads(), 0);
  EXPECT_LT(seconds, kRestyleSeconds);

  const std::string backend = cpu ? "--backend cpu --spp 2" : "--backend gl --spp 2";
  const Viewer::DisplayImage expected = render(viewer, o, backend + " --style 5=0.5 --style 32=1.5");
  // The sum rounds in float before the luxel's truncation to bytes (a luxel a level off at most),
  // and the GL render's luxels are bake.comp's, the GL window's the CPU's.
  EXPECT_LE(worstBetween(shown, expected), 1) << "the sliders' image is not the level's with its styles scaled";
  EXPECT_GT(worstBetween(render(viewer, o, backend), expected), 20) << "the sliders change nothing: the test cannot tell";
}

// Physical mode (the CPU window, whose exposure stays at 0): a slider scales its style's lights'
// emission in place (their colours and the light grid that weighs them): the image, every pixel,
// is render's of the level with that style scaled, with no import and no bake.
TEST_F(ViewerModesTest, APhysicalStyleSliderScalesItsLightsWithoutAReload) {
  save(roomMap(300) + styledLight(5, "64 64 -96", 250) + styledLight(0, "-64 -64 -96", 200));
  ViewerOptions o = optionsFor(ViewerBackend::Cpu, 2);
  o.lighting = LightingMode::Physical;
  o.lightingGiven = true;
  Viewer viewer(o);
  viewer.setDenoise(false);
  settled(viewer, 2);
  viewer.setStyleScale(5, 0.5f);
  viewer.setStyleScale(32, 0.0f);
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.stylesApplied() && viewer.samples() >= 2; })) << "the lights never took the sliders";
  const Viewer::DisplayImage shown = settled(viewer, 2);
  EXPECT_EQ(viewer.imports(), 1) << "the slider imported the level again";
  EXPECT_EQ(viewer.bakes(), 1) << "the slider baked the luxels again";
  const std::string flags = fmt::format("--backend cpu --lighting physical --bounces {} --exposure 0 --spp 2", o.bounces);
  const Viewer::DisplayImage expected = render(viewer, o, flags + " --style 5=0.5 --style 32=0");
  EXPECT_EQ(worstBetween(shown, expected), 0) << "the sliders' physical image is not the level's with its styles scaled";
  EXPECT_GT(worstBetween(render(viewer, o, flags), expected), 20) << "the sliders change nothing: the test cannot tell";
}

// A `_surface` light with a style: physical mode draws its template's faces as area emitters, and
// its slider scales them as `render --style` does (it scales the light before the template is
// made): the CPU window (exposure 0) against render, every pixel, with no import. (The GL
// window's exposure follows its image in time, so its upload, GlTracer::setSurfaceLights, is held
// by GlBeauty.ReplacedSurfaceTemplatesLightAsTheLevelBuiltWithThem.)
TEST_F(ViewerModesTest, APhysicalSliderScalesTheSurfaceEmittersOfItsStyle) {
  const std::string surfaceLight =
      "{\n\"classname\" \"light\"\n\"origin\" \"0 0 -100\"\n\"light\" \"40\"\n\"_surface\" \"wall\"\n\"style\" \"5\"\n}\n";
  save(roomMap(300) + surfaceLight);
  ViewerOptions o = optionsFor(ViewerBackend::Cpu, 2);
  o.lighting = LightingMode::Physical;
  o.lightingGiven = true;
  Viewer viewer(o);
  viewer.setDenoise(false);
  const Viewer::DisplayImage before = settled(viewer, 2);
  ASSERT_EQ(viewer.lightStyles(), std::vector<int>{5});
  viewer.setStyleScale(5, 0.25f);
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.stylesApplied() && viewer.samples() >= 2; })) << "the lights never took the sliders";
  const Viewer::DisplayImage shown = settled(viewer, 2);
  EXPECT_EQ(viewer.imports(), 1) << "the slider imported the level again";
  const std::string flags = fmt::format("--backend cpu --lighting physical --bounces {} --exposure 0 --spp 2", o.bounces);
  const Viewer::DisplayImage expected = render(viewer, o, flags + " --style 5=0.25");
  EXPECT_EQ(worstBetween(shown, expected), 0) << "the slider's emitters are not the template's scaled";
  EXPECT_GT(worstBetween(before, expected), 20) << "the slider changes nothing: the test cannot tell";
}

// Faithful light at each pixel's point (--luxels off): the sliders scale the lights each window's
// tracer reads (the GL window's through GlTracer::setLights): every pixel as render's of the level
// with those styles scaled, with no import.
TEST_P(ViewerStyleSlidersTest, SlidersScaleTheLightsOfThePerPixelView) {
  save(roomMap(300) + styledLight(5, "64 64 -96", 250) + styledLight(0, "-64 -64 -96", 200));
  ViewerOptions o = optionsFor(GetParam(), 2);
  o.luxels = false;
  Viewer viewer(o);
  settled(viewer, 2);
  viewer.setStyleScale(5, 0.5f);
  viewer.setStyleScale(32, 1.5f);
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.stylesApplied() && viewer.samples() >= 2; })) << "the lights never took the sliders";
  const Viewer::DisplayImage shown = settled(viewer, 2);
  EXPECT_EQ(viewer.imports(), 1) << "the slider imported the level again";
  const std::string flags = GetParam() == ViewerBackend::Cpu ? "--backend cpu --luxels off --spp 2" : "--backend gl --luxels off --spp 2";
  const Viewer::DisplayImage expected = render(viewer, o, flags + " --style 5=0.5 --style 32=1.5");
  EXPECT_LE(worstBetween(shown, expected), 1) << "the sliders' image is not the level's with its styles scaled";
  EXPECT_GT(worstBetween(render(viewer, o, flags), expected), 20) << "the sliders change nothing: the test cannot tell";
}

// The compiled view (key 6) of a Quake 2 level with a style 1 light: that style's slider weighs
// its compiled lightmaps as the game's lightstyle string would, with no import: every pixel as
// render --lighting compiled --style's, in both windows.
TEST_P(ViewerStyleSlidersTest, ASliderWeighsTheCompiledLightmapsOfItsStyle) {
  BT_REQUIRE_SHARED(shared);
  ViewerOptions o = optionsFor(GetParam(), 1);
  o.map = (shared / "oracle/lit-games/maps_ericw-tools_testmaps_q2_lightmap_custom_scale.bsp").string();
  o.compiled = true;
  Viewer viewer(o);
  // The compiled view bakes nothing: a sample per pixel is the picture.
  const auto shownOnce = [&] {
    EXPECT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 1; }));
    EXPECT_TRUE(viewer.frame());
    return viewer.displayed();
  };
  shownOnce();
  ASSERT_EQ(viewer.lightStyles(), std::vector<int>{1});
  viewer.setStyleScale(1, 0.25f);
  const Viewer::DisplayImage shown = shownOnce();
  EXPECT_EQ(viewer.imports(), 1) << "the slider imported the level again";
  const std::string flags =
      GetParam() == ViewerBackend::Cpu ? "--backend cpu --lighting compiled --spp 1" : "--backend gl --lighting compiled --spp 1";
  const Viewer::DisplayImage expected = render(viewer, o, flags + " --style 1=0.25");
  EXPECT_LE(worstBetween(shown, expected), 1) << "the slider's compiled image is not the level's with its style weighed";
  EXPECT_GT(worstBetween(render(viewer, o, flags), expected), 20) << "the slider changes nothing: the test cannot tell";
}

// Key 7 on the same level: a slider weighs both sides of the heat map, the compiled lightmaps of
// its style and the faithful luxels, as render --lighting difference --style does, with no import.
// (The difference view needs the GL tracer.)
constexpr size_t kHeatStepsApart = 6; // a tenth of a percent of the 96x64 window

TEST_F(ViewerModesTest, TheDifferenceViewWeighsBothOfItsSidesByTheSliders) {
  BT_REQUIRE_SHARED(shared);
  ViewerOptions o = optionsFor(ViewerBackend::Gl, 4);
  o.map = (shared / "oracle/lit-games/maps_ericw-tools_testmaps_q2_lightmap_custom_scale.bsp").string();
  Viewer viewer(o);
  ASSERT_TRUE(viewer.showDifference()) << viewer.notice();
  const Viewer::DisplayImage atOne = settled(viewer, 4);
  ASSERT_EQ(viewer.lightStyles(), std::vector<int>{1});
  viewer.setStyleScale(1, 0.25f);
  const Viewer::DisplayImage shown = settled(viewer, 4);
  EXPECT_EQ(viewer.imports(), 1) << "the slider imported the level again";
  const std::string flags = "--backend gl --lighting difference --spp 4";
  const Viewer::DisplayImage expected = render(viewer, o, flags + " --style 1=0.25");
  const Viewer::DisplayImage unweighed = render(viewer, o, flags);
  std::printf("heat-map pixels apart: window and render %zu, render at 1 and at 0.25 %zu\n", pixelsApart(shown, expected),
              pixelsApart(unweighed, expected));
  // A heat colour is a step of 8 levels of the larger difference: a luxel that rounds the other
  // way on the GPU moves a pixel into the next colour, as the level at 1 on both sides shows.
  EXPECT_LE(pixelsApart(atOne, render(viewer, o, flags)), kHeatStepsApart);
  EXPECT_LE(pixelsApart(shown, expected), kHeatStepsApart)
      << "the slider's heat map is not the level's with its style weighed on both sides";
  EXPECT_GT(pixelsApart(unweighed, expected), 10 * kHeatStepsApart) << "the slider changes nothing: the test cannot tell";
}

INSTANTIATE_TEST_SUITE_P(Windows, ViewerStyleSlidersTest, ::testing::Values(ViewerBackend::Cpu, ViewerBackend::Gl),
                         [](const auto& info) { return std::string(info.param == ViewerBackend::Cpu ? "Cpu" : "Gl"); });

} // namespace
} // namespace bt
