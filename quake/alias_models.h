// The games' model files, as their engines load them: Quake's .mdl (modelgen.h), Quake 2's .md2
// (qfiles.h dmdl_t) and Quake 3's .md3 (qfiles.h md3Header_t). brushtrace draws a model as the
// game shows it standing still: its first frame and its default skin. Every count and offset is
// checked against the file before it is used, as the BSP readers do: a truncated or lying file
// is an ImportError naming it, never a read past its end.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace bt::quake {

// modelgen.h mdl_t: "IDPO", version 6.
struct MdlHeader {
  glm::vec3 scale{1.0f};
  glm::vec3 scaleOrigin{0.0f};
  int32_t numSkins = 0, skinWidth = 0, skinHeight = 0;
  int32_t numVerts = 0, numTris = 0, numFrames = 0;
};
inline constexpr size_t kMdlHeaderSize = 84;

// qfiles.h dmdl_t: "IDP2", version 8.
struct Md2Header {
  int32_t skinWidth = 0, skinHeight = 0, frameSize = 0;
  int32_t numSkins = 0, numXyz = 0, numSt = 0, numTris = 0, numGlCmds = 0, numFrames = 0;
  int32_t ofsSkins = 0, ofsSt = 0, ofsTris = 0, ofsFrames = 0, ofsGlCmds = 0, ofsEnd = 0;
};
inline constexpr size_t kMd2HeaderSize = 68;

// qfiles.h md3Header_t: "IDP3", version 15; and md3Surface_t, whose offsets count from the
// surface's own start.
struct Md3Header {
  int32_t numFrames = 0, numTags = 0, numSurfaces = 0, numSkins = 0;
  int32_t ofsFrames = 0, ofsTags = 0, ofsSurfaces = 0, ofsEnd = 0;
};
inline constexpr size_t kMd3HeaderSize = 108;
struct Md3Surface {
  std::string name;
  int32_t numFrames = 0, numShaders = 0, numVerts = 0, numTriangles = 0;
  int32_t ofsTriangles = 0, ofsShaders = 0, ofsSt = 0, ofsXyzNormals = 0, ofsEnd = 0;
};
inline constexpr size_t kMd3SurfaceSize = 108;
inline constexpr float kMd3XyzScale = 1.0f / 64.0f; // MD3_XYZ_SCALE

// One triangle corner of the first frame: model-space position and texture coordinates as the
// engine draws them, 0..1 across the skin (t down from the top row).
struct AliasCorner {
  glm::vec3 position{0.0f};
  glm::vec2 st{0.0f};
};

struct AliasSurface {
  // The skin it is drawn with: .md2 the first skin's path, .md3 the surface's first shader
  // name; empty for .mdl, whose skin is in AliasModel::skinIndices.
  std::string skin;
  std::vector<AliasCorner> corners; // three per triangle
};

struct AliasModel {
  std::vector<AliasSurface> surfaces;
  // .mdl only: the chosen skin (the first image of a skin group), palette indices, rows top
  // to bottom.
  int skinWidth = 0, skinHeight = 0;
  std::vector<uint8_t> skinIndices;
};

// Each throws ImportError naming `name` when the file is not such a model or lies about its size.
// `skin`: the .mdl skin (the entity's `skin` field); a number past the last is the first, as
// the engine falls back on it.
AliasModel readMdl(std::span<const uint8_t> bytes, std::string_view name, int skin = 0);
AliasModel readMd2(std::span<const uint8_t> bytes, std::string_view name);
AliasModel readMd3(std::span<const uint8_t> bytes, std::string_view name);
// By the file's magic ("IDPO", "IDP2", "IDP3").
AliasModel readAliasModel(std::span<const uint8_t> bytes, std::string_view name, int skin = 0);

} // namespace bt::quake
