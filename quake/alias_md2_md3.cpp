// Quake 2's .md2 (ref_gl Mod_LoadAliasModel) and Quake 3's .md3 (renderergl1 R_LoadMD3): each
// record found by an offset from the header, checked to lie in the file before it is read.
#include "quake/alias_models.h"

#include "quake/binary_reader.h"
#include "scene/diagnostics.h"

#include <algorithm>
#include <string>

namespace bt::quake {
namespace {

[[noreturn]] void fail(std::string_view name, const std::string& message) {
  throw ImportError(Diagnostic{Severity::Error, std::string(name), 0, 0, message});
}

// A reader over `count` records of `size` bytes at `offset`, or an error naming what lies outside.
LittleEndianReader records(std::span<const uint8_t> bytes, int64_t offset, int64_t count, size_t size, std::string_view name,
                           const char* what) {
  if (offset < 0 || count < 0 || !fits(bytes, uint64_t(offset), uint64_t(count) * size))
    fail(name, std::string("truncated model: ") + what + " past the end of the file");
  return LittleEndianReader(bytes.subspan(size_t(offset), size_t(count) * size));
}

Md2Header readMd2Header(std::span<const uint8_t> bytes, std::string_view name) {
  LittleEndianReader in = records(bytes, 0, 1, kMd2HeaderSize, name, "header");
  if (in.u32() != 0x32504449u) fail(name, "not a Quake 2 model (no IDP2 magic)");
  if (const int32_t version = in.i32(); version != 8) fail(name, "unsupported .md2 version " + std::to_string(version) + " (expected 8)");
  Md2Header h;
  for (int32_t* field : {&h.skinWidth, &h.skinHeight, &h.frameSize, &h.numSkins, &h.numXyz, &h.numSt, &h.numTris, &h.numGlCmds,
                         &h.numFrames, &h.ofsSkins, &h.ofsSt, &h.ofsTris, &h.ofsFrames, &h.ofsGlCmds, &h.ofsEnd})
    *field = in.i32();
  if (h.skinWidth < 1 || h.skinHeight < 1) fail(name, "bad skin size");
  if (h.numFrames < 1) fail(name, "no frames");
  if (h.numXyz < 0 || h.numXyz > (1 << 20)) fail(name, "bad vertex count " + std::to_string(h.numXyz));
  return h;
}

void checkIndex(int32_t index, int32_t count, std::string_view name, const char* what) {
  if (index < 0 || index >= count)
    fail(name, std::string("triangle ") + what + " index " + std::to_string(index) + " out of range (" + std::to_string(count) + ")");
}

} // namespace

AliasModel readMd2(std::span<const uint8_t> bytes, std::string_view name) {
  const Md2Header h = readMd2Header(bytes, name);
  AliasSurface surface;
  if (h.numSkins > 0) surface.skin = records(bytes, h.ofsSkins, 1, 64, name, "skin names").name(64);

  LittleEndianReader frame = records(bytes, h.ofsFrames, 1, 40 + size_t(std::max(h.numXyz, 0)) * 4, name, "first frame");
  const glm::vec3 scale = frame.vec3(), translate = frame.vec3();
  frame.skip(16); // name
  std::vector<glm::vec3> positions(size_t(h.numXyz));
  for (glm::vec3& p : positions) {
    const float x = frame.u8(), y = frame.u8(), z = frame.u8();
    frame.u8(); // lightnormalindex
    p = glm::vec3(x, y, z) * scale + translate;
  }
  LittleEndianReader stIn = records(bytes, h.ofsSt, h.numSt, 4, name, "st coordinates");
  std::vector<glm::vec2> st(size_t(h.numSt));
  for (glm::vec2& v : st) {
    const float s = stIn.i16();
    v = glm::vec2(s, float(stIn.i16())) / glm::vec2(float(h.skinWidth), float(h.skinHeight));
  }
  LittleEndianReader tris = records(bytes, h.ofsTris, h.numTris, 12, name, "triangles");
  surface.corners.reserve(size_t(h.numTris) * 3);
  for (int32_t i = 0; i < h.numTris; ++i) {
    int32_t xyz[3], stIndex[3];
    for (int32_t& v : xyz) checkIndex(v = tris.i16(), h.numXyz, name, "vertex");
    for (int32_t& v : stIndex) checkIndex(v = tris.i16(), h.numSt, name, "st");
    for (int k = 0; k < 3; ++k) surface.corners.push_back({positions[size_t(xyz[k])], st[size_t(stIndex[k])]});
  }
  AliasModel model;
  model.surfaces.push_back(std::move(surface));
  return model;
}

namespace {

Md3Surface readMd3Surface(LittleEndianReader& in, std::string_view name) {
  if (in.u32() != 0x33504449u) fail(name, "surface without its IDP3 magic");
  Md3Surface s;
  s.name = in.name(64);
  in.skip(4); // flags
  for (int32_t* field :
       {&s.numFrames, &s.numShaders, &s.numVerts, &s.numTriangles, &s.ofsTriangles, &s.ofsShaders, &s.ofsSt, &s.ofsXyzNormals, &s.ofsEnd})
    *field = in.i32();
  return s;
}

// One surface at `offset`: its first shader, and the first frame's vertices (XYZ in 1/64 units).
AliasSurface md3Surface(std::span<const uint8_t> bytes, const Md3Surface& s, int64_t offset, std::string_view name) {
  AliasSurface surface;
  if (s.numShaders > 0) surface.skin = records(bytes, offset + s.ofsShaders, 1, 68, name, "surface shaders").name(64);
  LittleEndianReader xyz = records(bytes, offset + s.ofsXyzNormals, s.numVerts, 8, name, "surface vertices");
  LittleEndianReader stIn = records(bytes, offset + s.ofsSt, s.numVerts, 8, name, "surface st");
  std::vector<AliasCorner> vertices(size_t(s.numVerts));
  for (AliasCorner& v : vertices) {
    const float x = xyz.i16(), y = xyz.i16(), z = xyz.i16();
    xyz.i16(); // normal
    v.position = glm::vec3(x, y, z) * kMd3XyzScale;
    const float u = stIn.f32();
    v.st = glm::vec2(u, stIn.f32());
  }
  LittleEndianReader tris = records(bytes, offset + s.ofsTriangles, s.numTriangles, 12, name, "surface triangles");
  surface.corners.reserve(size_t(s.numTriangles) * 3);
  for (int32_t i = 0; i < s.numTriangles * 3; ++i) {
    const int32_t v = tris.i32();
    checkIndex(v, s.numVerts, name, "vertex");
    surface.corners.push_back(vertices[size_t(v)]);
  }
  return surface;
}

} // namespace

AliasModel readMd3(std::span<const uint8_t> bytes, std::string_view name) {
  LittleEndianReader in = records(bytes, 0, 1, kMd3HeaderSize, name, "header");
  if (in.u32() != 0x33504449u) fail(name, "not a Quake 3 model (no IDP3 magic)");
  if (const int32_t version = in.i32(); version != 15) fail(name, "unsupported .md3 version " + std::to_string(version) + " (expected 15)");
  in.skip(64 + 4); // name, flags
  Md3Header h;
  for (int32_t* field : {&h.numFrames, &h.numTags, &h.numSurfaces, &h.numSkins, &h.ofsFrames, &h.ofsTags, &h.ofsSurfaces, &h.ofsEnd})
    *field = in.i32();
  if (h.numFrames < 1) fail(name, "no frames");
  if (h.numSurfaces < 0 || h.numSurfaces > 4096) fail(name, "bad surface count " + std::to_string(h.numSurfaces));
  AliasModel model;
  int64_t offset = h.ofsSurfaces;
  for (int32_t i = 0; i < h.numSurfaces; ++i) {
    LittleEndianReader header = records(bytes, offset, 1, kMd3SurfaceSize, name, "surface header");
    const Md3Surface s = readMd3Surface(header, name);
    model.surfaces.push_back(md3Surface(bytes, s, offset, name));
    if (s.ofsEnd < int32_t(kMd3SurfaceSize)) fail(name, "surface " + s.name + " ends before its header does");
    offset += s.ofsEnd;
  }
  return model;
}

} // namespace bt::quake
