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

// How a Quake 3 shader's first stage is drawn over what lies behind it (ioquake3 tr_shader.c
// ParseStage's blendFunc): Opaque (no blendFunc, or GL_ONE GL_ZERO), Add (`add`, GL_ONE GL_ONE:
// behind + image), Filter (`filter`, GL_DST_COLOR GL_ZERO or GL_ZERO GL_SRC_COLOR: behind x
// image), Blend (`blend`, GL_SRC_ALPHA GL_ONE_MINUS_SRC_ALPHA: by the image's alpha).
enum class ShaderBlend : uint8_t { Opaque, Add, Filter, Blend };

// One `q3map_sun` / `q3map_sunExt` line of a Quake 3 shader, as q3map2's ParseShaderFile keeps it.
struct Q3ShaderSun {
  float color[3] = {1.0f, 1.0f, 1.0f}; // as written (q3map2 normalises it to unit length)
  float intensity = 0.0f;              // photons
  float degrees = 0.0f;                // azimuth of the direction towards the sun (0 = +x, 90 = +y)
  float elevation = 0.0f;              // degrees above the horizon
  float deviance = 0.0f;               // q3map_sunExt: the penumbra, degrees (0: a hard sun)
  int samples = 1;                     // q3map_sunExt: how many suns q3map2 spreads it over
};

// What q3map2 reads from a Quake 3 shader for light (shaders.c ParseShaderFile, LoadShaderImages);
// all defaults for other games and for names no shader script defines. lighting/q3map2_shader_light.h
// turns it into lights; lighting/README.md ("Quake 3 in faithful mode") lists each key.
struct Q3ShaderLight {
  bool defined = false; // a shader script defines this name
  std::string script;   // that script, and the line its name is on (for messages)
  int line = 0;
  float surfaceLight = 0.0f;           // q3map_surfacelight: area light value
  float color[3] = {1.0f, 1.0f, 1.0f}; // q3map2's si->color: q3map_lightRGB, else the light image's mean
  bool hasLightRGB = false;            // q3map_lightRGB given (else color is the image's, white without one)
  std::string lightImage;              // q3map_lightImage, else the first stage's map, else skyParms' _up image
  float subdivide = 0.0f;              // q3map_lightSubdivide (0: the compiler's default, 120)
  float backsplashFraction = 0.05f;    // q3map_backsplash percent / 100 (default 5 %)
  float backsplashDistance = 23.0f;    // q3map_backsplash distance (default 23)
  std::vector<Q3ShaderSun> suns;       // q3map_sun / q3map_sunExt lines
  float skyLightValue = 0.0f;          // q3map_skylight value
  int skyLightIterations = 0;          // q3map_skylight iterations (at least 2)
  bool sky = false;                    // surfaceparm sky (q3map_sun implies it)
  bool nodraw = false;                 // surfaceparm nodraw
  bool nolightmap = false;             // surfaceparm nolightmap
};

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
  ShaderBlend blend = ShaderBlend::Opaque; // Quake 3 shaders only
  Q3ShaderLight q3;                        // Quake 3 shaders only
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
