// The byte layout of every struct the C++ side uploads and the shaders read, as the linked
// programs see it: each member's offset and each array's stride, queried from the driver
// (program interface queries, GL_OFFSET and GL_TOP_LEVEL_ARRAY_STRIDE), against offsetof and
// sizeof of the C++ mirror (scene/gpu_structs.h, renderer/gl/gl_structs.h). The headers'
// static_asserts pin the C++ side to the numbers in shaders/structs.glsl's comments; this pins
// the GLSL itself, so an edit on either side that moves a member fails here. The BVH nodes,
// brushes and sides have no GLSL struct (trace.glsl reads them as uvec4 rows), so they are not
// here; the wavefront buffers have no C++ mirror (gl_tracer.cpp asks the program for their
// strides).
#include "renderer/gl/gl_program.h"
#include "renderer/gl/gl_structs.h"
#include "renderer/gl/gl_tracer.h"
#include "tests/gl/test_scenes.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <cstddef>
#include <algorithm>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace bt::gl {
namespace {

struct Member {
  std::string name;
  size_t offset;
};
#define MEMBER(Struct, name)                                                                                                               \
  Member {                                                                                                                                 \
#name, offsetof(Struct, name)                                                                                                          \
  }

// The programs the structs live in, built once for the whole test program: aov.comp (faces,
// materials, camera) and the path tracer in both lighting modes (lights, surface lights,
// emitters, the light grid, the World block).
std::vector<GLuint> programs() {
  test::sharedGlContext(); // made before the programs, so that it is destroyed after them
  static std::vector<std::unique_ptr<ComputeProgram>> built;
  if (built.empty()) {
    const std::vector<std::string> defines = shaderDefines(TextureMode::Arrays, TraceLayout::Hardware);
    std::vector<std::string> physical = defines;
    physical.emplace_back("BT_LIGHTING_PHYSICAL");
    std::vector<std::string> faithful = defines;
    faithful.insert(faithful.end(), {"BT_FAITHFUL_DIRT", "BT_FAITHFUL_BOUNCE_DRAW"});
    built.push_back(std::make_unique<ComputeProgram>("aov.comp", defines));
    built.push_back(std::make_unique<ComputeProgram>("pathtrace.comp", physical));
    built.push_back(std::make_unique<ComputeProgram>("pathtrace.comp", faithful));
  }
  std::vector<GLuint> ids;
  for (const auto& p : built) ids.push_back(p->id());
  return ids;
}

// Every active resource of `interface` in `program` whose name starts with `prefix`.
std::set<std::string> resourcesNamed(GLuint program, GLenum interface, const std::string& prefix) {
  GLint count = 0, maxLength = 0;
  glGetProgramInterfaceiv(program, interface, GL_ACTIVE_RESOURCES, &count);
  glGetProgramInterfaceiv(program, interface, GL_MAX_NAME_LENGTH, &maxLength);
  std::set<std::string> names;
  std::string name(size_t(std::max(maxLength, 1)), '\0');
  for (GLint i = 0; i < count; ++i) {
    GLsizei length = 0;
    glGetProgramResourceName(program, interface, GLuint(i), maxLength, &length, name.data());
    const std::string n(name.data(), size_t(length));
    if (n.starts_with(prefix)) names.insert(n);
  }
  return names;
}

// The first program that has `prefix`'s members active (a program that does not read a buffer
// has none of its variables).
GLuint programWith(GLenum interface, const std::string& prefix) {
  for (GLuint program : programs())
    if (!resourcesNamed(program, interface, prefix).empty()) return program;
  return 0;
}

// `prefix` names the struct: "materials[0]." for an array of structs in a storage block,
// "lightGrid." for one struct, "World." for a uniform block. The driver's members must be
// exactly `members` (a member added on one side only fails too), at the C++ offsets, and an
// array's elements `stride` bytes apart (0: not an array).
void expectLayout(GLenum interface, const std::string& prefix, const std::vector<Member>& members, size_t stride) {
  SCOPED_TRACE(prefix);
  const GLuint program = programWith(interface, prefix);
  ASSERT_NE(program, 0u) << "no program has " << prefix << "* active";
  std::set<std::string> expected;
  for (const Member& m : members) expected.insert(prefix + m.name);
  EXPECT_EQ(resourcesNamed(program, interface, prefix), expected);
  for (const Member& m : members) {
    const std::string name = prefix + m.name;
    const GLuint index = glGetProgramResourceIndex(program, interface, name.c_str());
    ASSERT_NE(index, GL_INVALID_INDEX) << name;
    GLint offset = -1;
    const GLenum offsetProperty = GL_OFFSET;
    glGetProgramResourceiv(program, interface, index, 1, &offsetProperty, 1, nullptr, &offset);
    EXPECT_EQ(offset, GLint(m.offset)) << name;
    if (interface == GL_BUFFER_VARIABLE) {
      GLint topStride = -1;
      const GLenum strideProperty = GL_TOP_LEVEL_ARRAY_STRIDE;
      glGetProgramResourceiv(program, interface, index, 1, &strideProperty, 1, nullptr, &topStride);
      EXPECT_EQ(topStride, GLint(stride)) << name;
    }
  }
}

TEST(GlStructLayout, FacesAsTheShadersReadThem) {
  expectLayout(GL_BUFFER_VARIABLE, "faces[0].",
               {MEMBER(GpuFace, plane), MEMBER(GpuFace, origin), MEMBER(GpuFace, material), MEMBER(GpuFace, tangent),
                MEMBER(GpuFace, brush), MEMBER(GpuFace, bitangent), MEMBER(GpuFace, pad)},
               sizeof(GpuFace));
}

TEST(GlStructLayout, MaterialsAsTheShadersReadThem) {
  expectLayout(GL_BUFFER_VARIABLE, "materials[0].",
               {MEMBER(GlMaterial, baseHandle), MEMBER(GlMaterial, normalHandle), MEMBER(GlMaterial, emissiveHandle),
                MEMBER(GlMaterial, baseArray), MEMBER(GlMaterial, baseLayer), MEMBER(GlMaterial, normalArray),
                MEMBER(GlMaterial, normalLayer), MEMBER(GlMaterial, emissiveArray), MEMBER(GlMaterial, emissiveLayer),
                MEMBER(GlMaterial, size), MEMBER(GlMaterial, flags), MEMBER(GlMaterial, roughness), MEMBER(GlMaterial, metallic),
                MEMBER(GlMaterial, opacity), MEMBER(GlMaterial, baseTexels), MEMBER(GlMaterial, normalTexels),
                MEMBER(GlMaterial, emissiveTexels), MEMBER(GlMaterial, liquid)},
               sizeof(GlMaterial));
}

std::vector<Member> lightMembers() {
  return {MEMBER(GpuLight, origin),
          MEMBER(GpuLight, type),
          MEMBER(GpuLight, color),
          MEMBER(GpuLight, value),
          MEMBER(GpuLight, direction),
          MEMBER(GpuLight, cosOuter),
          MEMBER(GpuLight, formula),
          MEMBER(GpuLight, atten),
          MEMBER(GpuLight, falloff),
          MEMBER(GpuLight, anglescale),
          MEMBER(GpuLight, cosInner),
          MEMBER(GpuLight, deviance),
          MEMBER(GpuLight, flags),
          MEMBER(GpuLight, faithfulScale),
          MEMBER(GpuLight, dirtScale),
          MEMBER(GpuLight, dirtGain),
          MEMBER(GpuLight, dirtOffRadius),
          MEMBER(GpuLight, dirtOnRadius),
          MEMBER(GpuLight, skyMaterial),
          MEMBER(GpuLight, lightChannels),
          MEMBER(GpuLight, shadowChannels),
          MEMBER(GpuLight, sunTable),
          MEMBER(GpuLight, physicalIntensity),
          MEMBER(GpuLight, physicalInvReach),
          MEMBER(GpuLight, visBox),
          MEMBER(GpuLight, physicalHueSum)};
}

TEST(GlStructLayout, LightsAndSurfaceLightsAsTheShadersReadThem) {
  expectLayout(GL_BUFFER_VARIABLE, "lights[0].", lightMembers(), sizeof(GpuLight));
  expectLayout(GL_BUFFER_VARIABLE, "surfaceLights[0].", lightMembers(), sizeof(GpuLight));
}

TEST(GlStructLayout, EmittersAsTheShadersReadThem) {
  expectLayout(GL_BUFFER_VARIABLE, "emitters[0].",
               {MEMBER(GpuEmitter, v0), MEMBER(GpuEmitter, face), MEMBER(GpuEmitter, v1), MEMBER(GpuEmitter, area), MEMBER(GpuEmitter, v2),
                MEMBER(GpuEmitter, cdf)},
               sizeof(GpuEmitter));
}

// The grid header, then its cells in the same buffer (GlSceneBuffers uploads them back to back).
TEST(GlStructLayout, LightGridAsTheShadersReadIt) {
  expectLayout(GL_BUFFER_VARIABLE, "lightGrid.",
               {MEMBER(GpuLightGrid, origin), MEMBER(GpuLightGrid, cellSize), MEMBER(GpuLightGrid, dims), MEMBER(GpuLightGrid, fixedCount),
                MEMBER(GpuLightGrid, globalFirst), MEMBER(GpuLightGrid, globalCount), MEMBER(GpuLightGrid, physicalFirst),
                MEMBER(GpuLightGrid, physicalCount)},
               0);
  std::vector<Member> cells = {MEMBER(GpuLightCell, first), MEMBER(GpuLightCell, count)};
  for (Member& m : cells) m.offset += sizeof(GpuLightGrid);
  expectLayout(GL_BUFFER_VARIABLE, "lightCells[0].", cells, sizeof(GpuLightCell));
}

// The std140 uniform blocks: members named "Block.member".
TEST(GlStructLayout, CameraAndWorldBlocksAsTheShadersReadThem) {
  expectLayout(GL_UNIFORM, "Camera.",
               {MEMBER(GpuCamera, origin), MEMBER(GpuCamera, pad0), MEMBER(GpuCamera, forward), MEMBER(GpuCamera, pad1),
                MEMBER(GpuCamera, right), MEMBER(GpuCamera, pad2), MEMBER(GpuCamera, up), MEMBER(GpuCamera, pad3),
                MEMBER(GpuCamera, imageSize), MEMBER(GpuCamera, frameIndex), MEMBER(GpuCamera, seed), MEMBER(GpuCamera, firstFrame),
                MEMBER(GpuCamera, pad4), MEMBER(GpuCamera, pixelOffset)},
               0);
  expectLayout(
      GL_UNIFORM, "World.",
      {MEMBER(GpuWorld, minlight),        MEMBER(GpuWorld, range),         MEMBER(GpuWorld, scaledist),  MEMBER(GpuWorld, bouncescale),
       MEMBER(GpuWorld, faithfulBounces), MEMBER(GpuWorld, litwater),      MEMBER(GpuWorld, lightCount), MEMBER(GpuWorld, emitterCount),
       MEMBER(GpuWorld, emitterArea),     MEMBER(GpuWorld, physical),      MEMBER(GpuWorld, bounces),    MEMBER(GpuWorld, dirtMode),
       MEMBER(GpuWorld, dirtDepth),       MEMBER(GpuWorld, dirtAngle),     MEMBER(GpuWorld, dirtScale),  MEMBER(GpuWorld, dirtGain),
       MEMBER(GpuWorld, minlightDirt),    MEMBER(GpuWorld, overbrightOne), MEMBER(GpuWorld, ambient),    MEMBER(GpuWorld, skySize),
       MEMBER(GpuWorld, luxelDisplay),    MEMBER(GpuWorld, clampIndirect)},
      0);
}

} // namespace
} // namespace bt::gl
