// The program binary cache: file format checks without GL, and on the test's GL context a
// cached program that loads, and a corrupt one that falls back to compiling.
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_program.h"
#include "renderer/gl/gl_program_cache.h"
#include "renderer/gl/gl_tracer.h"
#include "tests/gl/test_scenes.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

namespace bt::gl {
namespace {

namespace fs = std::filesystem;

// A fresh directory under the system's temporary folder, removed with the object.
struct TempDir {
  fs::path path = fs::temp_directory_path() / ("bt-program-cache-" + std::to_string(std::random_device{}()));
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

std::string readFile(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeFile(const fs::path& file, const std::string& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

TEST(ProgramCache, StoresAndLoadsOnlyForTheSameKey) {
  TempDir dir;
  const ProgramCache cache(dir.path);
  const std::string key = programCacheKey("void main() {}", "vendor", "renderer", "4.5");
  const ProgramBinary binary{42, {1, 2, 3, 4, 5}, {{ProgramBindingPoint::Uniform, 3, 2}, {ProgramBindingPoint::StorageBlock, 0, 7}}};
  cache.store("a.comp", key, binary);
  const auto loaded = cache.load("a.comp", key);
  ASSERT_TRUE(loaded);
  EXPECT_EQ(loaded->format, 42u);
  EXPECT_EQ(loaded->data, binary.data);
  EXPECT_EQ(loaded->bindings, binary.bindings);
  // Another driver version: another key, so never this binary.
  EXPECT_FALSE(cache.load("a.comp", programCacheKey("void main() {}", "vendor", "renderer", "4.6")));
  // Nothing but the entry itself is left in the directory (the temporary file was renamed).
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator()), 1);
}

TEST(ProgramCache, RejectsTruncatedAndForeignFiles) {
  TempDir dir;
  const ProgramCache cache(dir.path);
  const std::string key = programCacheKey("source", "v", "r", "1");
  cache.store("a.comp", key, ProgramBinary{7, std::vector<uint8_t>(100, 9)});
  const fs::path file = cache.fileFor("a.comp", key);
  const std::string whole = readFile(file);
  for (size_t length : {size_t{0}, size_t{5}, size_t{20}, whole.size() - 1}) {
    writeFile(file, whole.substr(0, length));
    EXPECT_FALSE(cache.load("a.comp", key)) << "truncated to " << length << " bytes";
  }
  writeFile(file, whole + "x");
  EXPECT_FALSE(cache.load("a.comp", key)) << "trailing garbage";
  writeFile(file, std::string(whole.size(), '\x5a'));
  EXPECT_FALSE(cache.load("a.comp", key)) << "garbage";
}

TEST(ProgramCache, EnvironmentPicksTheDirectoryOrDisablesIt) {
  const char* savedXdg = std::getenv("XDG_CACHE_HOME");
  const std::string xdg = savedXdg ? savedXdg : "";
  setenv("XDG_CACHE_HOME", "/tmp/bt-xdg", 1);
  unsetenv("BT_SHADER_CACHE");
  EXPECT_EQ(ProgramCache::fromEnvironment().directory(), fs::path("/tmp/bt-xdg/brushtrace"));
  // NVIDIA: off unless forced (its driver caches shaders itself).
  EXPECT_FALSE(ProgramCache::fromEnvironment("NVIDIA Corporation").enabled());
  setenv("BT_SHADER_CACHE", "1", 1);
  EXPECT_TRUE(ProgramCache::fromEnvironment("NVIDIA Corporation").enabled());
  setenv("BT_SHADER_CACHE", "0", 1);
  EXPECT_FALSE(ProgramCache::fromEnvironment().enabled());
  setenv("BT_SHADER_CACHE", "off", 1);
  EXPECT_FALSE(ProgramCache::fromEnvironment().enabled());
  unsetenv("BT_SHADER_CACHE");
  if (savedXdg)
    setenv("XDG_CACHE_HOME", xdg.c_str(), 1);
  else
    unsetenv("XDG_CACHE_HOME");
}

TEST(ProgramCache, CorruptBinaryFallsBackToCompiling) {
  GlContext& context = test::sharedGlContext();
  GLint formats = 0;
  glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &formats);
  if (formats == 0) GTEST_SKIP() << context.info().renderer << " offers no program binary formats (Mesa: shader cache disabled)";
  const int errorsBefore = context.debugErrorCount();
  TempDir dir;
  const ProgramCache cache(dir.path);
  const auto defines = shaderDefines(TextureMode::Arrays);
  {
    ComputeProgram first("aov.comp", defines, cache);
    EXPECT_FALSE(first.loadedFromCache());
  }
  {
    ComputeProgram second("aov.comp", defines, cache);
    EXPECT_TRUE(second.loadedFromCache());
  }
  ASSERT_EQ(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator()), 1);
  const fs::path file = fs::directory_iterator(dir.path)->path();
  std::string bytes = readFile(file);
  // Flip bits in the driver's binary (the end of the file), keeping our header intact: only
  // the driver can tell, and glProgramBinary must leave the program unlinked.
  for (size_t i = bytes.size() - 64; i < bytes.size(); ++i) bytes[i] = static_cast<char>(bytes[i] ^ 0xa5);
  writeFile(file, bytes);
  {
    ComputeProgram third("aov.comp", defines, cache);
    EXPECT_FALSE(third.loadedFromCache());
    // The compiled program works: AOVs of the test room.
    const Scene scene = test::makeTestRoom();
    GlTracer tracer(context, scene, TextureMode::Arrays);
    tracer.setProgramCache(cache);
    const AovImages aov = tracer.renderAovs(test::testCamera(32, 16), 32, 16);
    EXPECT_NE(std::count(aov.face.begin(), aov.face.end(), AovImages::kNothingHit), static_cast<long>(aov.face.size()));
  }
  // The bad file was replaced by a good one.
  ComputeProgram fourth("aov.comp", defines, cache);
  EXPECT_TRUE(fourth.loadedFromCache());
  EXPECT_EQ(context.debugErrorCount(), errorsBefore);
}

// A program loaded from the cache (its binding points applied again) renders what the compiled
// one rendered.
TEST(ProgramCache, CachedProgramRendersTheSameAovs) {
  GlContext& context = test::sharedGlContext();
  GLint formats = 0;
  glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &formats);
  if (formats == 0) GTEST_SKIP() << context.info().renderer << " offers no program binary formats (Mesa: shader cache disabled)";
  TempDir dir;
  const Scene scene = test::makeTestRoom();
  const CameraBasis camera = test::testCamera(48, 32);
  GlTracer compiled(context, scene, TextureMode::Arrays);
  compiled.setProgramCache(ProgramCache(dir.path));
  const AovImages a = compiled.renderAovs(camera, 48, 32);
  GlTracer loaded(context, scene, TextureMode::Arrays);
  loaded.setProgramCache(ProgramCache(dir.path));
  const AovImages b = loaded.renderAovs(camera, 48, 32);
  EXPECT_EQ(a.face, b.face);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.albedo, b.albedo);
  EXPECT_NE(std::count(a.face.begin(), a.face.end(), AovImages::kNothingHit), static_cast<long>(a.face.size()));
}

} // namespace
} // namespace bt::gl
