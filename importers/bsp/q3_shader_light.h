// What q3map2 reads from Quake 3 shader scripts for light (shaders.c ParseShaderFile and
// LoadShaderImages): the keys of Material::q3 (scene/material.h). The light compiler reads them
// for .map sources and compiled levels alike, so both importers call this.
#pragma once

#include "importers/bsp/pk3.h"
#include "importers/bsp/q3_shaders.h"
#include "scene/diagnostics.h"
#include "scene/material.h"

#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace bt::bsp {

// The light image's mean colour as q3map2 takes it (LoadShaderImages): the sum of every texel's
// bytes, ColorNormalize'd (the brightest channel 1; black gives white).
void setColorFromImage(Q3ShaderLight& light, const Image& image);

// Gives every material its shader's light keys and its first stage's blend (Material::blend;
// `shaders`: readQuake3Shaders), with the colour q3map2 takes where the shader has no
// q3map_lightRGB: the mean of its light image
// (q3map_lightImage, the first stage's map, skyParms' _up), else of its editor image or the
// image named like the shader, else white (q3map2's 64x64 white default image). `filesRead`,
// when given, receives the files the images came from.
void readQuake3ShaderLight(std::vector<Material>& materials, const Quake3Shaders& shaders, const GameFiles& files, Diagnostics& diagnostics,
                           std::vector<std::string>* filesRead = nullptr);

} // namespace bt::bsp
