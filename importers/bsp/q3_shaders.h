// Quake 3's shader scripts (scripts/*.shader), read and walked once per import into one record
// per shader: what the engine draws with it (its image, alphaFunc, sky box: q3_textures.h) and
// what q3map2 lights with (its keys: q3_shader_light.h).
#pragma once

#include "importers/bsp/pk3.h"
#include "scene/diagnostics.h"
#include "scene/material.h"

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace bt::bsp {

// One shader's light keys, and its qer_editorImage (the first image q3map2 tries for the
// shader's own image, which lights in its colour when the light image is missing).
struct ParsedShaderLight {
  Q3ShaderLight light;
  std::string editorImage;
};

struct Quake3Shader {
  // The image that shows it best in the engine: the first stage's `map` (not $lightmap), else
  // its qer_editorImage; empty when it names neither.
  std::string image;
  AlphaTest alphaTest = AlphaTest::None;   // the alphaFunc of its first stage that has one
  ShaderBlend blend = ShaderBlend::Opaque; // its first stage's blendFunc
  std::optional<std::string> skyBox;       // skyParms' far box ("env/space1" for env/space1_rt.tga), "" for "-"
  ParsedShaderLight light;                 // q3map2's keys
};

// By lowercase name, q3map2's `:q3map` suffix dropped; the first definition of a name wins, as
// q3map2's ShaderInfoForShader and the engine find the first.
using Quake3Shaders = std::map<std::string, Quake3Shader>;

// Every shader of one script. A key with a missing or malformed number warns in `diagnostics`
// with `scriptName` and its line, and reads as atof would (0); so does a shader whose name is
// not followed by `{` (q3map2 stops there; the preview goes on) and a nameless block.
Quake3Shaders parseShaderScript(std::string_view text, const std::string& scriptName, Diagnostics& diagnostics);

// Every script of the game's files (scripts/*.shader, earlier files first). `filesRead`, when
// given, receives the files on disk the scripts came from (a .pk3 for those inside one).
Quake3Shaders readQuake3Shaders(const GameFiles& files, Diagnostics& diagnostics, std::vector<std::string>* filesRead = nullptr);

// One field of every shader of a script, for tests and the fuzz harness.
std::map<std::string, std::string> parseShaderImages(std::string_view scriptText);
std::map<std::string, AlphaTest> parseShaderAlphaTests(std::string_view scriptText);
std::map<std::string, ShaderBlend> parseShaderBlends(std::string_view scriptText);
std::map<std::string, std::string> parseShaderSkyBoxes(std::string_view scriptText); // shaders with skyParms only
std::map<std::string, ParsedShaderLight> parseShaderLights(std::string_view text, const std::string& scriptName, Diagnostics& diagnostics);

} // namespace bt::bsp
