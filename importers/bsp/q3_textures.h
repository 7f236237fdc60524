// Quake 3 materials: shader names → images (TGA/JPEG/PNG: textures/image.cpp) in the game files.
#pragma once

#include "importers/bsp/pk3.h"
#include "importers/bsp/q3_shaders.h"
#include "scene/diagnostics.h"
#include "scene/material.h"
#include "scene/scene.h"

#include <map>
#include <string>
#include <vector>

namespace bt::bsp {

// Loads the base colour of each material named by a Quake 3 shader: the image its shader names
// (`shaders`: readQuake3Shaders), else an image file with the shader's own name (.tga, .jpg,
// .png), and its alphaFunc. The material's size becomes the image's. Materials found nowhere
// stay missing. `filesRead`, when given, receives the files on disk the images were read from (a
// .pk3 for those inside one).
void resolveQuake3Materials(std::vector<Material>& materials, const Quake3Shaders& shaders, const GameFiles& files,
                            Diagnostics& diagnostics, std::vector<std::string>* filesRead = nullptr);
// The same for a few materials, reading the scripts for them (a model's skins).
void resolveQuake3Materials(std::vector<Material>& materials, const GameFiles& files, Diagnostics& diagnostics,
                            std::vector<std::string>* filesRead = nullptr);

// Quake 3's sky (Scene::sky), as ioquake3 draws it (code/renderergl1/tr_shader.c ParseSkyParms,
// tr_sky.c DrawSkyBox): the far box of the first sky shader a face uses, its six images
// <farbox>_{rt,bk,lf,ft,up,dn}.tga (else .jpg, .png: R_FindImageFile's other formats) from
// `files`, clamped to their edges. A sky shader without a far box, or one whose images are not
// all there (with a warning naming the files tried), shows the mean colour of its first stage's
// image (the material's base colour) in every direction.
void loadQuake3Sky(Scene& scene, const GameFiles& files, const Quake3Shaders& shaders, std::vector<std::string>* filesRead = nullptr);

} // namespace bt::bsp
