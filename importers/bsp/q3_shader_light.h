// What q3map2 reads from Quake 3 shader scripts for light (shaders.c ParseShaderFile and
// LoadShaderImages): the keys of Material::q3 (scene/material.h). The light compiler reads them
// for .map sources and compiled levels alike, so both importers call this.
#pragma once

#include "importers/bsp/pk3.h"
#include "scene/diagnostics.h"
#include "scene/material.h"

#include <map>
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

// Every shader of one script, by lowercase name (the first definition of a name wins, as
// q3map2's ShaderInfoForShader finds the first). A key with a missing or malformed number warns
// in `diagnostics` with `scriptName` and its line, and reads as atof would (0); so does a shader
// whose name is not followed by `{` (q3map2 stops there; the preview goes on).
std::map<std::string, ParsedShaderLight> parseShaderLights(std::string_view text, const std::string& scriptName, Diagnostics& diagnostics);

// The light image's mean colour as q3map2 takes it (LoadShaderImages): the sum of every texel's
// bytes, ColorNormalize'd (the brightest channel 1; black gives white).
void setColorFromImage(Q3ShaderLight& light, const Image& image);

// Reads scripts/*.shader of `files` and gives every material its shader's light keys, with the
// colour q3map2 takes where the shader has no q3map_lightRGB: the mean of its light image
// (q3map_lightImage, the first stage's map, skyParms' _up), else of its editor image or the
// image named like the shader, else white (q3map2's 64x64 white default image). `filesRead`,
// when given, receives the files the scripts and images came from.
void readQuake3ShaderLight(std::vector<Material>& materials, const GameFiles& files, Diagnostics& diagnostics,
                           std::vector<std::string>* filesRead = nullptr);

} // namespace bt::bsp
