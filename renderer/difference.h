// `--lighting difference`: where the preview and the compile disagree. Each pixel is the largest
// channel difference between the compiled view and the faithful one, both as the display shows
// them (the PNG's bytes: exposure, tonemap and sRGB applied), drawn as a heat map:
//   0 black, 8 steps of 1/255 blue, 16 green, 24 yellow, 32 or more red, linear in between.
// 32 steps (12.5 % of the display's range) is the full scale: a mapper's eye sees a step of a few
// levels on a flat wall, and anything past 32 is simply wrong.
#pragma once

#include "renderer/render.h"

#include <cstdint>
#include <vector>

namespace bt {

inline constexpr int kDifferenceFullScale = 32; // display steps of 1/255 shown red

// The heat map's colour (display, sRGB 0..1) for a difference of `steps` display levels.
glm::vec3 differenceColour(int steps);

// The heat map (display colours, RGB bytes) of two pictures' display bytes (displayPixels).
std::vector<uint8_t> differencePixels(const std::vector<uint8_t>& compiled, const std::vector<uint8_t>& faithful);

// The heat map of two renders of one view; its beauty is linear, so that the faithful tonemap at
// exposure 0 writes differenceColour exactly. AOVs are `compiled`'s.
RenderImage differenceImage(const RenderImage& compiled, const RenderImage& faithful, const OutputSettings& output);

} // namespace bt
