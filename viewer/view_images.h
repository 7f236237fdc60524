// What the viewer's images become on screen and on disk, the same for both tracers: the albedo
// and normal views' display bytes, and F12's pair of files.
#pragma once

#include "renderer/gl/gl_tracer.h"
#include "renderer/render.h"
#include "viewer/view_modes.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace bt {

// The GL tracer's AOVs as the CPU tracer's RenderImage holds them (beauty left empty).
RenderImage aovImage(const gl::AovImages& aovs);

// The fullbright, normal or flat view of `image` as display bytes (RGBA8, rows top to bottom), as
// render --aov albedo, normal and face write them; nothing hit is black in the normal view.
std::vector<uint8_t> aovRgba(const RenderImage& image, ViewMode mode);

// RGB display bytes (displayPixels) as the window's RGBA8.
std::vector<uint8_t> rgbToRgba(const std::vector<uint8_t>& rgb);

// Writes <stem>-NNN.png (the first number free) and <stem>-NNN.exr into `folder` and returns the
// PNG's path. Throws when either cannot be written, leaving neither (each is written to a
// temporary name and renamed by writeImage).
std::filesystem::path writeScreenshot(const std::filesystem::path& folder, const std::string& stem, const RenderImage& image,
                                      const OutputSettings& output);

} // namespace bt
