// The CPU backend: renders a RenderScene into a linear image plus AOVs, on all cores.
#pragma once

#include "renderer/camera.h"
#include "renderer/render.h"
#include "renderer/cpu/integrator.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace bt {

RenderImage renderCpu(const RenderScene& scene, const Camera& camera, const RenderSettings& settings,
                      const std::function<void(const RenderProgress&)>& progress = {});

// The AOVs alone (beauty left black, samples 0): what an albedo, normal, depth or face output
// needs, without the cost of lighting every pixel.
RenderImage renderAovsCpu(const RenderScene& scene, const Camera& camera, int width, int height, int threads = 0);

} // namespace bt
