// A headless OpenGL 4.5 core context through EGL, owned by one object and passed explicitly.
//
// Platforms tried, in order:
//   1. EGL_EXT_platform_device: enumerate the EGL devices (NVIDIA's driver and Mesa both list
//      theirs) and take the first on which a GL 4.5 core context can be made current.
//   2. EGL_MESA_platform_surfaceless: Mesa without a display server (llvmpipe on CI).
// The context has no surface (EGL_KHR_surfaceless_context): compute shaders write images.
#pragma once

#include <memory>
#include <string>

namespace bt::gl {

struct GlContextInfo {
  std::string platform;               // "device" or "surfaceless"
  std::string vendor;                 // GL_VENDOR
  std::string renderer;               // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string version;                // GL_VERSION
  bool bindlessTextures = false;      // GL_ARB_bindless_texture
  bool anisotropicFiltering = false;  // GL_ARB_texture_filter_anisotropic / EXT
  int maxTextureUnits = 0;            // GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS
  bool softwareRenderer = false;      // GL emulated on the CPU: Mesa's llvmpipe, softpipe, swrast
  bool parallelShaderCompile = false; // GL_KHR/ARB_parallel_shader_compile: compiles run on driver threads
};

class GlContext {
public:
  // Makes a context current on the calling thread. Throws GlError with one line that says why,
  // per platform tried, when none works.
  static std::unique_ptr<GlContext> createHeadless();
  // Wraps a GL 4.5 core context that something else made current (a GLFW window, see
  // viewer/gl_window.h) and owns; `platform` names it in info().
  static std::unique_ptr<GlContext> adoptCurrent(std::string platform);
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  const GlContextInfo& info() const { return info_; }
  // createHeadless leaves the new context current; with several, switch back with this.
  void makeCurrent() const;
  // Debug builds (or BT_GL_DEBUG=1) turn on KHR_debug output; messages of type error are
  // counted here (and printed) so tests can assert that a render raised none.
  int debugErrorCount() const { return debugErrors_; }

private:
  struct Egl;
  GlContext(std::unique_ptr<Egl> egl, std::string platform);
  void queryInfo();
  void enableDebugOutput();
  static void debugCallback(unsigned source, unsigned type, unsigned id, unsigned severity, int length, const char* message,
                            const void* self);

  std::unique_ptr<Egl> egl_;
  GlContextInfo info_;
  int debugErrors_ = 0;
};

} // namespace bt::gl
