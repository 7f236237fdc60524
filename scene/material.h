// Materials: the textures a face samples, one Material per distinct texture name.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace bt {

// An 8-bit RGBA image, rows top to bottom as Quake stores miptex. Base colour and emissive
// maps hold sRGB-encoded values; normal, roughness and metallic maps hold linear values.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba; // width * height * 4

  bool empty() const { return width <= 0 || height <= 0; }
  const uint8_t* texel(int x, int y) const { return &rgba[(static_cast<size_t>(y) * width + x) * 4]; }
};

// Where a material's base colour came from; "missing" means a generated checker placeholder.
enum class TextureSource { Missing, Wad2, Wad3, Miptex, Wal, LooseImage };

// How the base colour's alpha cuts holes in a face. FromImage: alpha >= 0.5 is solid where the
// image has any texel below 255 ('{' textures, loose images with alpha), else no test; Quake 3
// shaders set None or their alphaFunc, since Quake 3 draws an image's alpha only when told.
enum class AlphaTest : uint8_t { FromImage, None, Gt0, Lt128, Ge128 };

struct Material {
  std::string name; // texture name as the map spells it
  int width = 64;   // size in texels: texture coordinates are divided by it to sample
  int height = 64;
  TextureSource source = TextureSource::Missing;
  std::string sourcePath; // file the base colour was read from (WAD, image), empty if missing

  Image baseColor; // sRGB, alpha = coverage ('{' textures)
  Image normal;    // tangent-space normal map, empty when absent
  Image roughness; // R channel, empty when absent (then `roughnessValue`)
  Image metallic;  // R channel, empty when absent (then `metallicValue`)
  Image emissive;  // sRGB; Quake fullbright texels (palette 224..255) land here too

  AlphaTest alphaTest = AlphaTest::FromImage;
  // Quake's scrolling sky only (Sky_LoadTexture in QuakeSpasm's gl_sky.c): the front layer, the
  // left half of baseColor with its palette index 0 clear (alpha 0, black), which the level's
  // Scene::sky takes; baseColor itself stays the texture as the WAD holds it. Empty otherwise.
  Image skyFront;
  float roughnessValue = 0.8f;
  float metallicValue = 0.0f;

  bool missing() const { return source == TextureSource::Missing; }
};

const char* toString(TextureSource source);

} // namespace bt
