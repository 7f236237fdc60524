// Quake's .mdl, as GLQuake's Mod_LoadAliasModel and gl_mesh.c BuildTris read it.
#include "quake/alias_models.h"

#include "quake/binary_reader.h"
#include "scene/diagnostics.h"

#include <string>

namespace bt::quake {
namespace {

[[noreturn]] void fail(std::string_view name, const std::string& message) {
  throw ImportError(Diagnostic{Severity::Error, std::string(name), 0, 0, message});
}

// Throws unless `count` records of `size` bytes lie in what is left of the file.
void need(const LittleEndianReader& in, int64_t count, size_t size, std::string_view name, const char* what) {
  if (count < 0 || uint64_t(count) * size > in.remaining())
    fail(name, std::string("truncated model: ") + what + " past the end of the file");
}

MdlHeader readHeader(LittleEndianReader& in, std::string_view name) {
  need(in, 1, kMdlHeaderSize, name, "header");
  if (in.u32() != 0x4f504449u) fail(name, "not a Quake model (no IDPO magic)"); // "IDPO"
  if (const int32_t version = in.i32(); version != 6) fail(name, "unsupported .mdl version " + std::to_string(version) + " (expected 6)");
  MdlHeader h;
  h.scale = in.vec3();
  h.scaleOrigin = in.vec3();
  in.skip(4 + 12); // boundingradius, eyeposition
  h.numSkins = in.i32();
  h.skinWidth = in.i32();
  h.skinHeight = in.i32();
  h.numVerts = in.i32();
  h.numTris = in.i32();
  h.numFrames = in.i32();
  in.skip(4 + 4 + 4); // synctype, flags, size
  if (h.numSkins < 1 || h.skinWidth < 1 || h.skinHeight < 1 || h.skinWidth > 4096 || h.skinHeight > 4096)
    fail(name,
         "bad skin count or size (" + std::to_string(h.numSkins) + " skins of " + std::to_string(h.skinWidth) + "x" +
             std::to_string(h.skinHeight) + ")");
  if (h.numVerts < 0 || h.numTris < 0 || h.numFrames < 1) fail(name, "bad vertex, triangle or frame count");
  return h;
}

// The skins: each a single image (type 0) or a group of images after their intervals; the
// engine shows a group's first image at time 0.
std::vector<uint8_t> readSkins(LittleEndianReader& in, const MdlHeader& h, int wanted, std::string_view name) {
  const size_t pixels = size_t(h.skinWidth) * size_t(h.skinHeight);
  std::vector<uint8_t> chosen;
  if (wanted < 0 || wanted >= h.numSkins) wanted = 0;
  for (int32_t i = 0; i < h.numSkins; ++i) {
    need(in, 1, 4, name, "skin");
    int32_t images = 1;
    if (in.i32() != 0) {
      need(in, 1, 4, name, "skin group");
      images = in.i32();
      need(in, images, 4, name, "skin group intervals");
      if (images < 1) fail(name, "empty skin group");
      in.skip(size_t(images) * 4);
    }
    need(in, images, pixels, name, "skin");
    if (i == wanted) {
      chosen.resize(pixels);
      for (uint8_t& p : chosen) p = in.u8();
      in.skip(pixels * size_t(images - 1));
    } else {
      in.skip(pixels * size_t(images));
    }
  }
  return chosen;
}

struct StVert {
  bool onseam = false;
  int32_t s = 0, t = 0;
};
struct Triangle {
  bool facesFront = true;
  int32_t vertex[3] = {};
};

// The first frame's vertices: a single frame, or the first of a group.
std::vector<glm::vec3> readFirstFrame(LittleEndianReader& in, const MdlHeader& h, std::string_view name) {
  need(in, 1, 4, name, "frame");
  if (in.i32() != 0) {
    need(in, 1, 12, name, "frame group");
    const int32_t frames = in.i32();
    in.skip(8); // bboxmin, bboxmax
    if (frames < 1) fail(name, "empty frame group");
    need(in, frames, 4, name, "frame group intervals");
    in.skip(size_t(frames) * 4);
  }
  need(in, 1, 24, name, "frame");
  in.skip(24); // bboxmin, bboxmax, name[16]
  need(in, h.numVerts, 4, name, "frame vertices");
  std::vector<glm::vec3> positions(size_t(h.numVerts));
  for (glm::vec3& p : positions) {
    const float x = in.u8(), y = in.u8(), z = in.u8();
    in.u8(); // lightnormalindex
    p = h.scale * glm::vec3(x, y, z) + h.scaleOrigin;
  }
  return positions;
}

} // namespace

AliasModel readMdl(std::span<const uint8_t> bytes, std::string_view name, int skin) {
  LittleEndianReader in(bytes);
  const MdlHeader h = readHeader(in, name);
  AliasModel model;
  model.skinWidth = h.skinWidth;
  model.skinHeight = h.skinHeight;
  model.skinIndices = readSkins(in, h, skin, name);

  need(in, h.numVerts, 12, name, "st vertices");
  std::vector<StVert> st(size_t(h.numVerts));
  for (StVert& v : st) {
    v.onseam = in.i32() != 0;
    v.s = in.i32();
    v.t = in.i32();
  }
  need(in, h.numTris, 16, name, "triangles");
  std::vector<Triangle> triangles(size_t(h.numTris));
  for (Triangle& t : triangles) {
    t.facesFront = in.i32() != 0;
    for (int32_t& v : t.vertex) {
      v = in.i32();
      if (v < 0 || v >= h.numVerts)
        fail(name, "triangle vertex " + std::to_string(v) + " out of range (" + std::to_string(h.numVerts) + " vertices)");
    }
  }
  const std::vector<glm::vec3> positions = readFirstFrame(in, h, name);

  AliasSurface& surface = model.surfaces.emplace_back();
  surface.corners.reserve(triangles.size() * 3);
  for (const Triangle& t : triangles)
    for (int32_t v : t.vertex) {
      // A back-facing triangle's seam vertex samples the skin's back half (BuildTris).
      float s = float(st[size_t(v)].s);
      if (!t.facesFront && st[size_t(v)].onseam) s += float(h.skinWidth / 2);
      const glm::vec2 uv((s + 0.5f) / float(h.skinWidth), (float(st[size_t(v)].t) + 0.5f) / float(h.skinHeight));
      surface.corners.push_back({positions[size_t(v)], uv});
    }
  return model;
}

AliasModel readAliasModel(std::span<const uint8_t> bytes, std::string_view name, int skin) {
  if (bytes.size() >= 4) {
    switch (readU32(bytes, 0)) {
    case 0x4f504449u: return readMdl(bytes, name, skin); // IDPO
    case 0x32504449u: return readMd2(bytes, name);       // IDP2
    case 0x33504449u: return readMd3(bytes, name);       // IDP3
    default: break;
    }
  }
  fail(name, "not a model brushtrace reads (expected a Quake .mdl, Quake 2 .md2 or Quake 3 .md3)");
}

} // namespace bt::quake
