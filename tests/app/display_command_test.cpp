// `brushtrace render`'s display of physical light as users get it: the automatic exposure
// printed in the output line and stored in the EXR, `--exposure` winning over it, and
// `--denoise` (the PNG denoised, the EXR's default layer the raw beauty, the denoised one beside).
#include "tests/app/run_command.h"
#include "tests/test_data.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <regex>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

using bt::test::brushtrace;
using bt::test::CommandResult;
namespace fs = std::filesystem;
constexpr auto npos = std::string::npos;

struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name)
      : path(fs::temp_directory_path() / ("bt_display_cmd_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

std::string quoted(const fs::path& p) {
  return "'" + p.string() + "'";
}

// The automatic exposure the output line gives ("exposure +1.57 EV auto").
std::optional<float> printedAutoExposure(const std::string& out) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex(R"(exposure ([+-][0-9]+\.[0-9]+) EV auto)"))) return std::nullopt;
  return std::stof(m[1].str());
}

struct Exr {
  std::vector<std::string> channels;
  std::vector<float> pixels; // every channel, in the file's order
  float exposureEv = NAN;
  std::string exposure;
  std::vector<float> channel(const std::string& name) const {
    const size_t c = size_t(std::find(channels.begin(), channels.end(), name) - channels.begin());
    std::vector<float> values;
    if (c == channels.size()) return values;
    for (size_t i = c; i < pixels.size(); i += channels.size()) values.push_back(pixels[i]);
    return values;
  }
};

Exr readExr(const fs::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  Exr exr{spec.channelnames, std::vector<float>(size_t(spec.width) * spec.height * spec.nchannels)};
  in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, exr.pixels.data());
  exr.exposureEv = spec.get_float_attribute("brushtrace:exposureEV", NAN);
  exr.exposure = spec.get_string_attribute("brushtrace:exposure");
  return exr;
}

std::vector<uint8_t> readPng(const fs::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return {};
  std::vector<uint8_t> pixels(size_t(in->spec().width) * in->spec().height * in->spec().nchannels);
  in->read_image(0, 0, 0, in->spec().nchannels, OIIO::TypeDesc::UINT8, pixels.data());
  return pixels;
}

const std::string kPhysical = " --lighting physical --backend cpu --size 64x36 --seed 3";

// The Done-when line of issue 18: the same exposure within 1/3 EV at 4 and 64 spp, as `render`
// prints it and stores it. The default map (maps/start.map), and a LibreQuake level whose
// 4-spp image is dark and noisy: there a log-average of single pixels is 0.6 EV off, and the
// block means keep it within 0.05.
void expectSameExposureAt4And64Spp(const std::string& level) {
  SCOPED_TRACE(level.empty() ? "maps/start.map" : level);
  TempDir dir("spp");
  const CommandResult few = brushtrace("render " + level + " -o " + quoted(dir.path / "few.exr") + kPhysical + " --spp 4");
  const CommandResult many = brushtrace("render " + level + " -o " + quoted(dir.path / "many.exr") + kPhysical + " --spp 64");
  ASSERT_EQ(few.exitCode, 0) << few.err;
  ASSERT_EQ(many.exitCode, 0) << many.err;
  const std::optional<float> fewEv = printedAutoExposure(few.out), manyEv = printedAutoExposure(many.out);
  ASSERT_TRUE(fewEv && manyEv) << few.out << many.out;
  EXPECT_NEAR(*fewEv, *manyEv, 1.0f / 3.0f);
  const Exr exr = readExr(dir.path / "few.exr");
  EXPECT_NEAR(exr.exposureEv, *fewEv, 0.005f);
  EXPECT_EQ(exr.exposure, "auto");
}

TEST(RenderExposure, FourAndSixtyFourSppGiveTheSameExposure) {
  expectSameExposureAt4And64Spp("");
  const std::optional<fs::path> shared = bt::test::sharedDir();
  const fs::path level = shared ? *shared / "maps/librequake/lq1/maps/src/e3/lq_e3m1.map" : fs::path();
  if (!shared || !fs::exists(level))
    GTEST_SKIP() << "../shared/maps/librequake/lq1/maps/src/e3/lq_e3m1.map not found: only start.map was checked";
  expectSameExposureAt4And64Spp(quoted(level));
}

TEST(RenderExposure, AnExplicitExposureWinsAndFaithfulLightIsNotAutoExposed) {
  TempDir dir("given");
  const CommandResult zero = brushtrace("render -o " + quoted(dir.path / "zero.exr") + kPhysical + " --spp 2 --exposure 0");
  ASSERT_EQ(zero.exitCode, 0) << zero.err;
  EXPECT_NE(zero.out.find("physical lighting, exposure +0.00 EV, cpu)"), npos) << zero.out;
  const Exr exr = readExr(dir.path / "zero.exr");
  EXPECT_EQ(exr.exposureEv, 0.0f);
  EXPECT_EQ(exr.exposure, "given");
  const CommandResult faithful = brushtrace("render -o " + quoted(dir.path / "f.png") + " --backend cpu --size 64x36 --spp 1");
  ASSERT_EQ(faithful.exitCode, 0) << faithful.err;
  EXPECT_NE(faithful.out.find("1 spp, faithful lighting, cpu)"), npos) << faithful.out;
}

// sRGB(ACES(x)) as a byte, the display of an EXR value (the EXR holds the exposed beauty).
uint8_t displayByte(float x) {
  const float a = std::clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
  const float s = a <= 0.0031308f ? a * 12.92f : 1.055f * std::pow(a, 1.0f / 2.4f) - 0.055f;
  return uint8_t(std::lround(s * 255.0f));
}

TEST(RenderDenoise, PngShowsTheDenoisedImageAndExrKeepsTheRawBeauty) {
  TempDir dir("denoise");
  const std::string base = "render" + kPhysical + " --spp 4 --exposure 1";
  for (const char* out : {"raw.exr", "raw.png"}) ASSERT_EQ(brushtrace(base + " -o " + quoted(dir.path / out)).exitCode, 0);
  for (const char* out : {"dn.exr", "dn.png"}) {
    const CommandResult r = brushtrace(base + " --denoise -o " + quoted(dir.path / out));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find(", denoised, cpu)"), npos) << r.out;
  }
  const Exr raw = readExr(dir.path / "raw.exr"), dn = readExr(dir.path / "dn.exr");
  for (const char* c : {"R", "G", "B"}) EXPECT_EQ(dn.channel(c), raw.channel(c)) << "the default layer is the raw beauty: " << c;
  const std::vector<float> r = dn.channel("denoised.R"), g = dn.channel("denoised.G"), b = dn.channel("denoised.B");
  ASSERT_EQ(r.size(), size_t(64 * 36));
  EXPECT_NE(r, raw.channel("R"));
  // The PNG is the denoised layer as displayed, every pixel in colour, within rounding.
  const std::vector<uint8_t> png = readPng(dir.path / "dn.png");
  ASSERT_EQ(png.size(), r.size() * 3);
  int off = 0;
  for (size_t i = 0; i < r.size(); ++i)
    for (int c = 0; c < 3; ++c) off += std::abs(int(png[i * 3 + c]) - int(displayByte((c == 0 ? r : c == 1 ? g : b)[i]))) > 1;
  EXPECT_EQ(off, 0);
  EXPECT_NE(png, readPng(dir.path / "raw.png"));
}

// `bench --time-to-converged --backend cpu --reference`: the stored reference (a render's EXR) is
// read instead of rendered, its sample count from the EXR, the sweep stopping at a quarter of it;
// a reference of another size or view is refused with a message and exit code 1.
TEST(BenchCommand, TimeToConvergedReadsAStoredReference) {
  TempDir dir("bench_reference");
  const std::string start = quoted(bt::test::mapsDir() / "start.map");
  const std::string view = " --backend cpu --bounces 1 --size 32x18";
  const CommandResult ref = brushtrace("render " + start + " -o " + quoted(dir.path / "ref.exr") + view +
                                       " --lighting physical --exposure 0 --seed 24301 --spp 16 --quiet");
  ASSERT_EQ(ref.exitCode, 0) << ref.err;
  const std::string bench = "bench --time-to-converged " + view + " --reference " + quoted(dir.path / "ref.exr") + " ";
  const CommandResult run = brushtrace(bench + start);
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_NE(run.out.find("reference: stored, 16 spp"), npos) << run.out;
  EXPECT_EQ(run.out.find("reference: 16 spp in"), npos) << "rendered instead of read: " << run.out;
  EXPECT_NE(run.out.find("time to converged, cpu, denoiser off:"), npos) << run.out;
  EXPECT_NE(run.out.find("time to converged, cpu, denoiser on:"), npos) << run.out;
  EXPECT_EQ(run.out.find("  8 spp:"), npos) << "past a quarter of the reference's 16 spp: " << run.out;

  const CommandResult otherSize = brushtrace("bench --time-to-converged --backend cpu --bounces 1 --size 34x18 --reference " +
                                             quoted(dir.path / "ref.exr") + " " + start);
  EXPECT_EQ(otherSize.exitCode, 1);
  EXPECT_NE(otherSize.err.find("the reference is 32x18, the bench renders 34x18"), npos) << otherSize.err;
  const CommandResult otherLevel = brushtrace(bench + quoted(bt::test::mapsDir() / "curves.map"));
  EXPECT_EQ(otherLevel.exitCode, 1);
  EXPECT_NE(otherLevel.err.find("another level, camera or size"), npos) << otherLevel.err;
}

} // namespace
