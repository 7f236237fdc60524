// Writing rendered images (libpng, OpenEXR). Kept apart from the tracer so that what links the
// tracer alone (the GL tests and benchmark carried to a GPU machine) does not drag in
// OpenEXR.
#pragma once

#include "renderer/render.h"

#include <string>

namespace bt {

// .png: tonemapped sRGB of the chosen AOV (the denoised beauty where the image has one). .exr:
// linear beauty (exposure applied) as the default layer, with albedo.*, normal.*, depth.Z and,
// when denoised, denoised.* layers, moment2.Y (the second moment of the samples' luminance) where
// the tracer kept it, and the exposure in the header (brushtrace:exposureEV,
// brushtrace:exposure "auto" or "given"). Written to a temporary name and renamed.
// Throws std::runtime_error with the reason when the file cannot be written.
void writeImage(const std::string& path, const RenderImage& image, const OutputSettings& output);

// An EXR that writeImage wrote, read back: the linear beauty with the exposure taken out again
// (so the image the tracer gave), the albedo, normal and depth AOVs, the second moment where the
// file holds one (so the denoiser can be run again on it), and `samples` from the
// header's brushtrace:samples (0 in files written before it was stored). A stored reference for
// `brushtrace bench --time-to-converged --reference`. Throws std::runtime_error with the reason.
RenderImage readExrImage(const std::string& path);

} // namespace bt
