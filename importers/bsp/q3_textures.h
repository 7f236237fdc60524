// Quake 3 materials: shader names → images (TGA/JPEG/PNG via OpenImageIO) in the game files.
#pragma once

#include "importers/bsp/pk3.h"
#include "scene/diagnostics.h"
#include "scene/material.h"
#include "scene/scene.h"

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

// For each shader with `skyParms <farbox> <cloudheight> <nearbox>` in scripts/*.shader, its far
// box: "env/space1" for env/space1_rt.tga ..., empty for "-" (none). Keys are lowercase shader
// names.
std::map<std::string, std::string> parseShaderSkyBoxes(std::string_view scriptText);

// Loads the base colour of each material named by a Quake 3 shader: the image the shader
// scripts name for it, else an image file with the shader's own name (.tga, .jpg, .png). The
// material's size becomes the image's. Materials found nowhere stay missing. `filesRead`, when
// given, receives the files on disk the scripts and images were read from (a .pk3 for those
// inside one). `skyBoxes`, when given, receives parseShaderSkyBoxes of every script.
void resolveQuake3Materials(std::vector<Material>& materials, const GameFiles& files, Diagnostics& diagnostics,
                            std::vector<std::string>* filesRead = nullptr, std::map<std::string, std::string>* skyBoxes = nullptr);

// Quake 3's sky (Scene::sky), as ioquake3 draws it (code/renderergl1/tr_shader.c ParseSkyParms,
// tr_sky.c DrawSkyBox): the far box of the first sky shader a face uses, its six images
// <farbox>_{rt,bk,lf,ft,up,dn}.tga (else .jpg, .png: R_FindImageFile's other formats) from
// `files`, clamped to their edges. A sky shader without a far box, or one whose images are not
// all there (with a warning naming the files tried), shows the mean colour of its first stage's
// image (the material's base colour) in every direction.
void loadQuake3Sky(Scene& scene, const GameFiles& files, const std::map<std::string, std::string>& skyBoxes,
                   std::vector<std::string>* filesRead = nullptr);

} // namespace bt::bsp
