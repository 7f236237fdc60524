#include "tests/support/alias_model_writer.h"

#include <bit>
#include <cstring>

namespace bt::test {
namespace {

struct Writer {
  std::vector<uint8_t> bytes;
  void u8(uint8_t v) { bytes.push_back(v); }
  void i16(int16_t v) {
    u8(uint8_t(uint16_t(v) & 0xff));
    u8(uint8_t(uint16_t(v) >> 8));
  }
  void i32(int32_t v) {
    for (int k = 0; k < 4; ++k) u8(uint8_t(uint32_t(v) >> (8 * k)));
  }
  void f32(float v) { i32(std::bit_cast<int32_t>(v)); }
  void vec3(glm::vec3 v) { f32(v.x), f32(v.y), f32(v.z); }
  void name(const std::string& s, size_t size) {
    for (size_t k = 0; k < size; ++k) u8(k < s.size() ? uint8_t(s[k]) : 0);
  }
  void magic(const char* m) { name(m, 4); }
  void patch32(size_t at, int32_t v) {
    for (int k = 0; k < 4; ++k) bytes[at + size_t(k)] = uint8_t(uint32_t(v) >> (8 * k));
  }
};

void trivertx(Writer& w, glm::vec3 p) {
  w.u8(uint8_t(p.x)), w.u8(uint8_t(p.y)), w.u8(uint8_t(p.z)), w.u8(0);
}

} // namespace

std::vector<uint8_t> writeMdl(const TestMdl& m) {
  Writer w;
  w.magic("IDPO");
  w.i32(6);
  w.vec3(m.scale), w.vec3(m.origin);
  w.f32(1.0f), w.vec3(glm::vec3(0.0f)); // boundingradius, eyeposition
  for (int v : {int(m.skins.size()), m.skinWidth, m.skinHeight, int(m.st.size()), int(m.triangles.size()), 1, 0, 0}) w.i32(v);
  w.f32(1.0f); // size
  for (const std::vector<uint8_t>& skin : m.skins) {
    w.i32(0);
    w.bytes.insert(w.bytes.end(), skin.begin(), skin.end());
  }
  for (const TestMdl::StVert& v : m.st) w.i32(v.onseam ? 0x20 : 0), w.i32(v.s), w.i32(v.t);
  for (const TestMdl::Triangle& t : m.triangles) {
    w.i32(t.facesFront ? 1 : 0);
    for (int v : t.vertex) w.i32(v);
  }
  w.i32(0); // a single frame
  trivertx(w, glm::vec3(0.0f)), trivertx(w, glm::vec3(0.0f));
  w.name("frame1", 16);
  for (glm::vec3 p : m.positions) trivertx(w, p);
  return w.bytes;
}

std::vector<uint8_t> writeMd2(const TestMd2& m) {
  Writer w;
  w.magic("IDP2");
  w.i32(8);
  const int32_t frameSize = 40 + 4 * int32_t(m.positions.size());
  const int32_t ofsSkins = 68, ofsSt = ofsSkins + 64, ofsTris = ofsSt + 4 * int32_t(m.st.size());
  const int32_t ofsFrames = ofsTris + 12 * int32_t(m.triangles.size()), ofsEnd = ofsFrames + frameSize;
  for (int32_t v : {m.skinWidth, m.skinHeight, frameSize, 1, int32_t(m.positions.size()), int32_t(m.st.size()), int32_t(m.triangles.size()),
                    0, 1, ofsSkins, ofsSt, ofsTris, ofsFrames, ofsEnd, ofsEnd})
    w.i32(v);
  w.name(m.skin, 64);
  for (const auto& st : m.st) w.i16(st[0]), w.i16(st[1]);
  for (const TestMd2::Triangle& t : m.triangles) {
    for (int16_t v : t.xyz) w.i16(v);
    for (int16_t v : t.st) w.i16(v);
  }
  w.vec3(m.scale), w.vec3(m.translate);
  w.name("frame1", 16);
  for (glm::vec3 p : m.positions) trivertx(w, p);
  return w.bytes;
}

std::vector<uint8_t> writeMd3(const std::vector<TestMd3Surface>& surfaces) {
  Writer w;
  w.magic("IDP3");
  w.i32(15);
  w.name("test.md3", 64);
  w.i32(0);
  // numFrames numTags numSurfaces numSkins ofsFrames ofsTags ofsSurfaces ofsEnd (frames and tags: none read)
  for (int32_t v : {1, 0, int32_t(surfaces.size()), 0, 108, 108, 108, 0}) w.i32(v);
  for (const TestMd3Surface& s : surfaces) {
    const size_t start = w.bytes.size();
    const int32_t nv = int32_t(s.positions.size()), nt = int32_t(s.triangles.size());
    const int32_t ofsShaders = 108, ofsTriangles = ofsShaders + 68, ofsSt = ofsTriangles + 12 * nt, ofsXyz = ofsSt + 8 * nv;
    w.magic("IDP3");
    w.name(s.name, 64);
    for (int32_t v : {0, 1, 1, nv, nt, ofsTriangles, ofsShaders, ofsSt, ofsXyz, ofsXyz + 8 * nv}) w.i32(v);
    w.name(s.shader, 64), w.i32(0);
    for (const auto& t : s.triangles)
      for (int32_t v : t) w.i32(v);
    for (glm::vec2 st : s.st) w.f32(st.x), w.f32(st.y);
    for (glm::vec3 p : s.positions) {
      for (float c : {p.x, p.y, p.z}) w.i16(int16_t(c * 64.0f));
      w.i16(0);
    }
    (void)start;
  }
  w.patch32(104, int32_t(w.bytes.size())); // ofsEnd
  return w.bytes;
}

TestMdl squareMdl(int size, uint8_t index) {
  TestMdl m;
  m.skins.push_back(std::vector<uint8_t>(size_t(m.skinWidth * m.skinHeight), index));
  m.positions = {{0, 0, 0}, {float(size), 0, 0}, {float(size), float(size), 0}, {0, float(size), 0}};
  m.st = {{false, 0, 0}, {false, 7, 0}, {false, 7, 7}, {false, 0, 7}};
  m.triangles = {{true, {0, 1, 2}}, {true, {0, 2, 3}}};
  return m;
}

} // namespace bt::test
