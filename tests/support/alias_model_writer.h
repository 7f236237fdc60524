// Tiny .mdl, .md2 and .md3 files written in the tests, in the layouts quake/alias_models.h reads:
// never game data. Positions are written exactly (the .mdl/.md2 frames as bytes with scale 1 and
// origin 0, the .md3's in 1/64 units), so that a test knows each vertex.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace bt::test {

struct TestMdl {
  int skinWidth = 8, skinHeight = 8;
  std::vector<std::vector<uint8_t>> skins; // palette indices, one image per skin
  struct StVert {
    bool onseam = false;
    int s = 0, t = 0;
  };
  std::vector<StVert> st;
  struct Triangle {
    bool facesFront = true;
    std::array<int, 3> vertex{};
  };
  std::vector<Triangle> triangles;
  std::vector<glm::vec3> positions; // the frame's, 0..255 whole numbers
  glm::vec3 scale{1.0f}, origin{0.0f};
};
std::vector<uint8_t> writeMdl(const TestMdl& m);

struct TestMd2 {
  int skinWidth = 16, skinHeight = 16;
  std::string skin;
  std::vector<glm::vec3> positions; // 0..255 whole numbers
  std::vector<std::array<int16_t, 2>> st;
  struct Triangle {
    std::array<int16_t, 3> xyz{}, st{};
  };
  std::vector<Triangle> triangles;
  glm::vec3 scale{1.0f}, translate{0.0f};
};
std::vector<uint8_t> writeMd2(const TestMd2& m);

struct TestMd3Surface {
  std::string name = "surface", shader;
  std::vector<glm::vec3> positions; // multiples of 1/64
  std::vector<glm::vec2> st;
  std::vector<std::array<int32_t, 3>> triangles;
};
std::vector<uint8_t> writeMd3(const std::vector<TestMd3Surface>& surfaces);

// A one-skin .mdl: a square of two triangles from (0,0,0) to (size,size,0) seen from +Z, its skin
// `skinWidth` x `skinHeight` of one palette index.
TestMdl squareMdl(int size, uint8_t index);

} // namespace bt::test
