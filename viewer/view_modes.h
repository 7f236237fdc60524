// The viewer's view modes, as ericw-tools' lightpreview and QuakeSpasm's r_ cvars show a level
// (the preview denoiser's schedule is renderer/denoise_fade.h). Pure image arithmetic, the same for both tracers' windows.
//
//   1 lit         the lighting mode's picture (faithful, physical, compiled: keys 4-7)
//   2 fullbright  the textures without light (r_fullbright 1): the albedo AOV, as render --aov albedo
//   3 normals     the face normal, 0.5 + 0.5 n (render --aov normal)
//   8 light only  the light on a white surface (r_lightmap 1): each pixel's picture divided by its
//                 texture colour, in the engine's texture (gamma) space for faithful and compiled
//                 light (the engine draws texture x lightmap there), in linear radiance for
//                 physical light (a Lambertian surface's outgoing light is albedo x irradiance / pi)
//   9 flat        each surface in its own flat colour, unlit (r_drawflat 1): the colour render
//                 --aov face gives the face, three bytes of a hash of its index (QuakeSpasm draws a
//                 random colour per surface)
#pragma once

#include "renderer/denoise_fade.h" // denoiseShare: physical mode's denoised share, which the viewer shows
#include "renderer/render.h"

#include <glm/vec3.hpp>
#include <vector>

namespace bt {

enum class ViewMode { Beauty, Fullbright, Normal, LightOnly, Flat };

const char* toString(ViewMode mode); // "lit", "fullbright", "normals", "light only", "flat"

// The light alone of `image` (its beauty over its albedo AOV): `engineSpace` for faithful and
// compiled light, else linear. A pixel of a black texel (a channel under 1/255) has no light to
// show and is black in that channel; nothing hit stays as it is.
std::vector<glm::vec3> lightAlone(const RenderImage& image, bool engineSpace);

} // namespace bt
