// The storage-buffer binding points the shaders declare against the C++ Binding enum
// (renderer/gl/gl_structs.h): no two buffers share a point, and the light grid's buffers sit
// where GlSceneBuffers binds them. A clash compiles and runs; it just reads the wrong data.
#include "renderer/gl/gl_program.h"
#include "renderer/gl/gl_structs.h"
#include "renderer/gl/gl_textures.h"

#include <gtest/gtest.h>

#include <cctype>
#include <map>
#include <regex>
#include <string>

namespace bt::gl {
namespace {

// The values of the #defines of integers in the embedded shader files (shaders/gl_bindings.glsl
// names every binding point).
std::map<std::string, int> definedNumbers() {
  std::map<std::string, int> defines;
  const std::regex define(R"(#define\s+(\w+)\s+(\d+)u?\b)");
  for (const ShaderFile& file : embeddedShaders()) {
    const std::string source(file.source);
    for (auto it = std::sregex_iterator(source.begin(), source.end(), define); it != std::sregex_iterator(); ++it)
      defines[(*it)[1].str()] = std::stoi((*it)[2].str());
  }
  return defines;
}

// Name -> N for every match of `declaration` (group 1: the number or the #define naming it,
// group 2: the name) in the embedded shader files; -1 where a name has no value.
std::map<std::string, int> declaredNumbers(const std::regex& declaration) {
  const std::map<std::string, int> defines = definedNumbers();
  std::map<std::string, int> numbers;
  for (const ShaderFile& file : embeddedShaders()) {
    const std::string source(file.source);
    for (auto it = std::sregex_iterator(source.begin(), source.end(), declaration); it != std::sregex_iterator(); ++it) {
      const std::string value = (*it)[1].str();
      const auto defined = defines.find(value);
      numbers[(*it)[2].str()] = std::isdigit(static_cast<unsigned char>(value[0])) ? std::stoi(value)
          : defined != defines.end()                                               ? defined->second
                                                                                   : -1;
    }
  }
  return numbers;
}

// Every `layout(std430, binding = N) ... buffer Name`: Name -> N.
std::map<std::string, int> storageBufferBindings() {
  return declaredNumbers(
      std::regex(R"(layout\s*\(\s*std430\s*,\s*binding\s*=\s*(\w+)\s*\)\s*(?:readonly\s+|writeonly\s+)*buffer\s+(\w+))"));
}

// Every `layout(binding = N) uniform [u]samplerBuffer name` (the traversal's texel views): name -> N.
std::map<std::string, int> texelViewUnits() {
  return declaredNumbers(std::regex(R"(layout\s*\(\s*binding\s*=\s*(\w+)\s*\)\s*uniform\s+u?samplerBuffer\s+(\w+))"));
}

// The faithful bake's buffers (shaders/bake.comp), which take the wavefront's points: no program
// uses both (drivers need offer only 16 storage blocks to a compute shader).
bool bakeBuffer(const std::string& name) {
  return name == "LuxelSamples" || name == "LuxelSumBuffer" || name == "SkyDome";
}

TEST(ShaderBindings, EveryStorageBufferHasItsOwnBindingPoint) {
  const std::map<std::string, int> bindings = storageBufferBindings();
  ASSERT_GE(bindings.size(), 8u); // nodes, brushes and sides are read as texels only
  std::map<int, std::string> owner;
  for (const auto& [name, point] : bindings) {
    EXPECT_GE(point, 0) << name << "'s binding names no #define of shaders/gl_bindings.glsl";
    if (bakeBuffer(name)) continue;
    const auto [it, inserted] = owner.emplace(point, name);
    EXPECT_TRUE(inserted) << name << " and " << it->second << " both use binding " << point;
  }
}

TEST(ShaderBindings, LightGridBuffersMatchTheEnum) {
  const std::map<std::string, int> bindings = storageBufferBindings();
  ASSERT_TRUE(bindings.contains("LightGridBuffer"));
  ASSERT_TRUE(bindings.contains("LightIndices"));
  EXPECT_EQ(bindings.at("LightGridBuffer"), int(kBindingLightGrid));
  EXPECT_EQ(bindings.at("LightIndices"), int(kBindingLightIndices));
  EXPECT_EQ(bindings.at("Lights"), int(kBindingLights));
}

TEST(ShaderBindings, BakeBuffersMatchTheEnumAndNoBufferOfTheirProgram) {
  const std::map<std::string, int> bindings = storageBufferBindings();
  for (const auto& [name, point] : {std::pair{"LuxelSamples", kBindingBakeSamples}, std::pair{"LuxelSumBuffer", kBindingBakeSums},
                                    std::pair{"SkyDome", kBindingBakeSkyDome}}) {
    ASSERT_TRUE(bindings.contains(name)) << name;
    EXPECT_EQ(bindings.at(name), int(point)) << name;
    for (const auto& [other, otherPoint] : bindings) // only the wavefront's buffers, which bake.comp does not include
      if (otherPoint == int(point) && other != name)
        EXPECT_TRUE(std::string(other).starts_with("Wavefront")) << other << " and " << name << " both use binding " << point;
  }
}

// GlTracer binds the wavefront form's per-pixel buffers (shaders/wavefront.glsl, pathtrace.comp).
TEST(ShaderBindings, WavefrontBuffersMatchTheEnum) {
  const std::map<std::string, int> bindings = storageBufferBindings();
  for (const auto& [name, point] :
       {std::pair{"WavefrontRays", kBindingWavefrontRays}, std::pair{"WavefrontHits", kBindingWavefrontHits},
        std::pair{"WavefrontPaths", kBindingWavefrontPaths}, std::pair{"WavefrontEndedCount", kBindingWavefrontEndedCount}}) {
    ASSERT_TRUE(bindings.contains(name)) << name;
    EXPECT_EQ(bindings.at(name), int(point)) << name;
  }
}

// GlSceneBuffers binds the views on the TexelUnit units; the material texture arrays take units
// 0 .. kMaxTextureArrays - 1, so a view there would be overwritten by GlTextures::bind.
TEST(ShaderBindings, TexelViewsSitOnTheirUnitsAfterTheTextureArrays) {
  const std::map<std::string, int> units = texelViewUnits();
  const std::map<std::string, int> expected = {
      {"nodeTexels", kTexelNodes}, {"brushTexels", kTexelBrushes}, {"sideTexels", kTexelSides}, {"faceTexels", kTexelFaces}};
  EXPECT_EQ(units, expected);
  for (const auto& [name, unit] : units) {
    EXPECT_GE(unit, kMaxTextureArrays) << name;
    EXPECT_LT(unit, int(kTexelUnitEnd)) << name;
  }
}

} // namespace
} // namespace bt::gl
