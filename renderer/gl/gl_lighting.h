// The lighting the GL tracer takes, from the CPU reference's RenderScene: both tracers light
// from one classification of faces and one light list, so they cannot drift apart.
#pragma once

#include "lighting/render_scene.h"
#include "renderer/gl/gl_tracer.h"

namespace bt::gl {

GlLighting lightingFor(const RenderScene& scene);

} // namespace bt::gl
