// The storage-buffer binding points the shaders declare against the C++ Binding enum
// (renderer/gl/gl_structs.h): no two buffers share a point, and the light grid's buffers sit
// where GlSceneBuffers binds them. A clash compiles and runs; it just reads the wrong data.
#include "renderer/gl/gl_program.h"
#include "renderer/gl/gl_structs.h"

#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <string>

namespace bt::gl {
namespace {

// Every `layout(std430, binding = N) ... buffer Name` of the embedded shader files: Name -> N.
std::map<std::string, int> storageBufferBindings() {
  std::map<std::string, int> bindings;
  const std::regex declaration(R"(layout\s*\(\s*std430\s*,\s*binding\s*=\s*(\d+)\s*\)\s*(?:readonly\s+|writeonly\s+)*buffer\s+(\w+))");
  for (const ShaderFile& file : embeddedShaders()) {
    const std::string source(file.source);
    for (auto it = std::sregex_iterator(source.begin(), source.end(), declaration); it != std::sregex_iterator(); ++it)
      bindings[(*it)[2].str()] = std::stoi((*it)[1].str());
  }
  return bindings;
}

TEST(ShaderBindings, EveryStorageBufferHasItsOwnBindingPoint) {
  const std::map<std::string, int> bindings = storageBufferBindings();
  ASSERT_GE(bindings.size(), 9u);
  std::map<int, std::string> owner;
  for (const auto& [name, point] : bindings) {
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

} // namespace
} // namespace bt::gl
