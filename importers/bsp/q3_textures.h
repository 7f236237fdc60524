// Quake 3 materials: shader names → images (TGA/JPEG/PNG via OpenImageIO) in the game files.
#pragma once

#include "importers/bsp/pk3.h"
#include "scene/diagnostics.h"
#include "scene/material.h"

#include <map>
#include <string>
#include <vector>

namespace bt::bsp {

// For each shader defined in scripts/*.shader, the image that shows it best: the first stage's
// `map` (not $lightmap) or else its qer_editorimage. Keys are lowercase shader names.
std::map<std::string, std::string> parseShaderImages(std::string_view scriptText);

// For each shader defined in scripts/*.shader, the alphaFunc of its first stage that has one
// (GT0, LT128, GE128), else None. Keys are lowercase shader names.
std::map<std::string, AlphaTest> parseShaderAlphaTests(std::string_view scriptText);

// Loads the base colour of each material named by a Quake 3 shader: the image the shader
// scripts name for it, else an image file with the shader's own name (.tga, .jpg, .png). The
// material's size becomes the image's. Materials found nowhere stay missing. `filesRead`, when
// given, receives the files on disk the scripts and images were read from (a .pk3 for those
// inside one).
void resolveQuake3Materials(std::vector<Material>& materials, const GameFiles& files, Diagnostics& diagnostics,
                            std::vector<std::string>* filesRead = nullptr);

} // namespace bt::bsp
