// The headless context, GL error reporting and shader assembly.
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_program.h"
#include "tests/gl/test_scenes.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace bt::gl {
namespace {

TEST(GlContext, HeadlessContextIsGl45WithCompute) {
  // A second context beside the shared one: both must stay usable.
  GlContext& shared = test::sharedGlContext();
  auto context = GlContext::createHeadless();
  ASSERT_TRUE(context);
  const GlContextInfo& info = context->info();
  EXPECT_TRUE(info.platform.starts_with("device") || info.platform == "surfaceless") << info.platform;
  EXPECT_GE(epoxy_gl_version(), 45) << info.version;
  EXPECT_GE(info.maxTextureUnits, 16) << "the arrays path binds 16 sampler2DArrays";
  std::printf("GL context: %s, %s, %s, bindless %s\n", info.platform.c_str(), info.renderer.c_str(), info.version.c_str(),
              info.bindlessTextures ? "yes" : "no");
  const std::string renderer = info.renderer;
  context.reset();
  EXPECT_EQ(shared.info().renderer, renderer);
  EXPECT_EQ(glGetString(GL_RENDERER), nullptr) << "destroying the current context leaves none current";
  shared.makeCurrent();
  ASSERT_NE(glGetString(GL_RENDERER), nullptr);
  EXPECT_EQ(reinterpret_cast<const char*>(glGetString(GL_RENDERER)), renderer);
}

// Where KHR_debug output is on: Debug builds, and BT_GL_DEBUG=1, which tests/gl/CMakeLists.txt
// sets for these suites under ctest.
bool debugOutputOn() {
#ifdef NDEBUG
  const char* env = std::getenv("BT_GL_DEBUG");
  return env && *env && std::string_view(env) != "0";
#else
  return true;
#endif
}

TEST(GlContext, ErrorNamesTheCallThatCausedIt) {
  GlContext& context = test::sharedGlContext();
  const int debugErrorsBefore = context.debugErrorCount();
  try {
    BT_GL(glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1u << 20, 0));
    FAIL() << "an out-of-range binding point must raise a GL error";
  } catch (const GlError& e) {
    const std::string text = e.what();
    EXPECT_NE(text.find("glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1u << 20, 0)"), std::string::npos) << text;
    EXPECT_NE(text.find("GL_INVALID_VALUE"), std::string::npos) << text;
    EXPECT_NE(text.find("gl_context_test.cpp"), std::string::npos) << text;
  }
  // The error queue was drained: the next call reports only itself.
  EXPECT_NO_THROW(BT_GL(glFinish()));
  // With debug output on, the debug callback counted it too: the render tests' checks that a
  // render raised no GL error (debugErrorCount) are live, in CI's RelWithDebInfo build as well.
  if (debugOutputOn()) {
    EXPECT_EQ(context.debugErrorCount(), debugErrorsBefore + 1);
  }
}

TEST(ShaderAssembly, IncludesAreInlinedWithLineDirectives) {
  const std::vector<std::string> defines{"BT_TEXTURES_ARRAYS"};
  const std::string source = assembleShader("aov.comp", defines);
  EXPECT_TRUE(source.starts_with("#version 450\n#define BT_TEXTURES_ARRAYS\n")) << source.substr(0, 80);
  EXPECT_EQ(source.find("#include"), std::string::npos);
  EXPECT_EQ(source.find("GL_GOOGLE_include_directive"), std::string::npos);
  EXPECT_NE(source.find("struct GpuFace"), std::string::npos);
  // structs.glsl comes in through scene_buffers.glsl only once.
  EXPECT_EQ(source.find("struct GpuFace"), source.rfind("struct GpuFace"));
}

// TracerPrograms assembles each file once for all its define sets; the program cache's key is
// the text, so it must be assembleShader's to the byte.
TEST(ShaderAssembly, KeptSourcesAreAssembleShadersText) {
  ShaderSources sources;
  const std::vector<std::vector<std::string>> defineSets{
      {"BT_TEXTURES_BINDLESS", "BT_WAVEFRONT_SHADE"}, {"BT_TEXTURES_ARRAYS", "BT_LIGHTING_PHYSICAL"}, {}};
  for (const char* name : {"pathtrace.comp", "wavefront_trace.comp"})
    for (const auto& defines : defineSets) {
      const std::string kept = sources.assemble(name, defines), direct = assembleShader(name, defines);
      // Not EXPECT_EQ: the texts are 50-150 KB.
      EXPECT_TRUE(kept == direct) << name << " with " << defines.size() << " defines: " << kept.size() << " chars against " << direct.size()
                                  << ", first difference at "
                                  << std::mismatch(kept.begin(), kept.end(), direct.begin(), direct.end()).first - kept.begin();
    }
  EXPECT_THROW(sources.assemble("missing.comp", {}), GlError);
}

TEST(ShaderAssembly, CompileErrorNamesTheSourceFiles) {
  test::sharedGlContext();
  // Neither texture variant defined: textures.glsl's #error fires inside an included file.
  try {
    ComputeProgram program("aov.comp", {});
    FAIL() << "aov.comp without a texture variant must not compile";
  } catch (const GlError& e) {
    const std::string text = e.what();
    EXPECT_NE(text.find("aov.comp does not compile"), std::string::npos) << text;
    EXPECT_NE(text.find("textures.glsl"), std::string::npos) << text;
  }
  EXPECT_NO_THROW(ComputeProgram("aov.comp", shaderDefines(TextureMode::Arrays)));
}

} // namespace
} // namespace bt::gl
