#include "renderer/gl/gl_context.h"

#include "renderer/gl/gl_error.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string_view>
#include <optional>
#include <vector>

namespace bt::gl {

struct GlContext::Egl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;

  // The display is left initialised: eglGetPlatformDisplay hands every caller the same
  // display for a device, so eglTerminate here would pull it from under any other context on
  // it. (On NVIDIA, a context made after such a terminate also took 20 s and drew nothing.)
  ~Egl() {
    if (display == EGL_NO_DISPLAY || context == EGL_NO_CONTEXT) return;
    if (eglGetCurrentContext() == context) eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display, context);
  }
};

namespace {

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)); p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

// Debug builds, or any build with BT_GL_DEBUG=1 in the environment (for a carried release
// binary on another machine), get a debug context with KHR_debug output.
bool debugOutputWanted() {
#ifndef NDEBUG
  return true;
#else
  const char* env = std::getenv("BT_GL_DEBUG");
  return env && *env && std::string_view(env) != "0";
#endif
}

std::string eglErrorText() {
  return fmt::format("EGL error 0x{:04x}", eglGetError());
}

// Initialises `display` and makes a GL 4.5 core context current on it; on failure returns why.
std::optional<std::string> makeCurrentContext(EGLDisplay display, EGLContext& context) {
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) return "eglInitialize: " + eglErrorText();
  if (!hasExtension(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context"))
    return std::string("no EGL_KHR_surfaceless_context");
  if (!eglBindAPI(EGL_OPENGL_API)) return "eglBindAPI(EGL_OPENGL_API): " + eglErrorText();

  // The context never gets a surface, so it needs no config where EGL_KHR_no_config_context
  // allows that. Otherwise any GL config will do; EGL_SURFACE_TYPE must be said to not matter,
  // as its default (EGL_WINDOW_BIT) matches nothing on NVIDIA's device platform, which has no
  // window system.
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!hasExtension(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_no_config_context")) {
    const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_DONT_CARE, EGL_NONE};
    EGLint configCount = 0;
    if (!eglChooseConfig(display, configAttribs, &config, 1, &configCount) || configCount == 0)
      return "no EGL config with EGL_OPENGL_BIT, and no EGL_KHR_no_config_context";
  }

  const EGLint flags = debugOutputWanted() ? EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR : 0;
  const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                   4,
                                   EGL_CONTEXT_MINOR_VERSION,
                                   5,
                                   EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                   EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                   EGL_CONTEXT_FLAGS_KHR,
                                   flags,
                                   EGL_NONE};
  context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs);
  if (context == EGL_NO_CONTEXT) return "no GL 4.5 core context: " + eglErrorText();
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) return "eglMakeCurrent: " + eglErrorText();
  if (epoxy_gl_version() < 45) return fmt::format("GL version {} < 4.5", epoxy_gl_version() / 10.0);
  return std::nullopt;
}

// What an EGL device is, for messages: its DRM node if it has one, and the extensions that
// tell NVIDIA (EGL_NV_device_cuda) from Mesa's software device (EGL_MESA_device_software).
std::string describeDevice(EGLDeviceEXT device) {
  const char* extensions = eglQueryDeviceStringEXT(device, EGL_EXTENSIONS);
  std::string text;
  if (hasExtension(extensions, "EGL_EXT_device_drm"))
    if (const char* node = eglQueryDeviceStringEXT(device, EGL_DRM_DEVICE_FILE_EXT)) text = node;
  if (extensions && *extensions) text += (text.empty() ? "" : ", ") + std::string(extensions);
  return text.empty() ? "no device strings" : text;
}

} // namespace

std::unique_ptr<GlContext> GlContext::createHeadless() {
  const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  std::vector<std::string> reasons;

  // `platform` names it in info(); `detail` adds what the messages should say about it.
  auto tryDisplay = [&](EGLDisplay display, const std::string& platform, const std::string& detail) -> std::unique_ptr<GlContext> {
    const std::string name = detail.empty() ? platform : platform + " (" + detail + ")";
    auto egl = std::make_unique<Egl>();
    egl->display = display;
    if (display == EGL_NO_DISPLAY) {
      reasons.push_back(name + ": no display (" + eglErrorText() + ")");
      return nullptr;
    }
    if (auto why = makeCurrentContext(display, egl->context)) {
      reasons.push_back(name + ": " + *why);
      return nullptr;
    }
    auto context = std::unique_ptr<GlContext>(new GlContext(std::move(egl), platform));
    if (debugOutputWanted()) {
      std::fprintf(stderr, "brushtrace: GL context on EGL %s: %s\n", name.c_str(), context->info().renderer.c_str());
      for (const std::string& reason : reasons) std::fprintf(stderr, "brushtrace:   passed over %s\n", reason.c_str());
    }
    return context;
  };

  // NVIDIA's EGL lists device enumeration as part of EGL_EXT_device_base, Mesa's as
  // EGL_EXT_device_enumeration; either provides eglQueryDevicesEXT.
  const bool platformDevice = hasExtension(clientExtensions, "EGL_EXT_platform_device");
  const bool enumeration =
      hasExtension(clientExtensions, "EGL_EXT_device_enumeration") || hasExtension(clientExtensions, "EGL_EXT_device_base");
  if (platformDevice && enumeration) {
    EGLint count = 0;
    eglQueryDevicesEXT(0, nullptr, &count);
    std::vector<EGLDeviceEXT> devices(static_cast<size_t>(std::max(count, 0)));
    if (count > 0) eglQueryDevicesEXT(count, devices.data(), &count);
    for (EGLint i = 0; i < count; ++i) {
      const EGLDeviceEXT device = devices[static_cast<size_t>(i)];
      EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
      if (auto context = tryDisplay(display, fmt::format("device {}", i), describeDevice(device))) return context;
    }
    if (count <= 0) reasons.push_back("device: no EGL devices (" + eglErrorText() + ")");
  } else {
    reasons.push_back(fmt::format("device: the client extensions lack {} (they are: {})",
                                  platformDevice ? "EGL_EXT_device_enumeration / EGL_EXT_device_base" : "EGL_EXT_platform_device",
                                  clientExtensions ? clientExtensions : "none"));
  }

  if (hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (auto context = tryDisplay(display, "surfaceless", "")) return context;
  } else {
    reasons.push_back("surfaceless: no EGL_MESA_platform_surfaceless");
  }

  std::string text = "no headless GL 4.5 context (";
  for (size_t i = 0; i < reasons.size(); ++i) text += (i ? "; " : "") + reasons[i];
  throw GlError(text + ")");
}

GlContext::GlContext(std::unique_ptr<Egl> egl, std::string platform) : egl_(std::move(egl)) {
  info_.platform = std::move(platform);
  queryInfo();
  if (debugOutputWanted()) enableDebugOutput();
}

std::unique_ptr<GlContext> GlContext::adoptCurrent(std::string platform) {
  return std::unique_ptr<GlContext>(new GlContext(nullptr, std::move(platform)));
}

GlContext::~GlContext() = default;

void GlContext::makeCurrent() const {
  if (eglGetCurrentContext() == egl_->context) return;
  if (!eglMakeCurrent(egl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl_->context)) throw GlError("eglMakeCurrent: " + eglErrorText());
}

void GlContext::queryInfo() {
  auto str = [](GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return std::string(s ? s : "");
  };
  info_.vendor = str(GL_VENDOR);
  info_.renderer = str(GL_RENDERER);
  info_.version = str(GL_VERSION);
  for (std::string_view name : {"llvmpipe", "softpipe", "swrast"})
    info_.softwareRenderer = info_.softwareRenderer || info_.renderer.find(name) != std::string::npos;
  info_.bindlessTextures = epoxy_has_gl_extension("GL_ARB_bindless_texture");
  info_.anisotropicFiltering =
      epoxy_has_gl_extension("GL_ARB_texture_filter_anisotropic") || epoxy_has_gl_extension("GL_EXT_texture_filter_anisotropic");
  BT_GL(glGetIntegerv(GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS, &info_.maxTextureUnits));
  // As many compiler threads as the driver likes (0xFFFFFFFF): programs started early
  // (ComputeProgram::Deferred) then compile beside the import instead of after it.
  if (epoxy_has_gl_extension("GL_KHR_parallel_shader_compile")) {
    info_.parallelShaderCompile = true;
    BT_GL(glMaxShaderCompilerThreadsKHR(0xFFFFFFFFu));
  } else if (epoxy_has_gl_extension("GL_ARB_parallel_shader_compile")) {
    info_.parallelShaderCompile = true;
    BT_GL(glMaxShaderCompilerThreadsARB(0xFFFFFFFFu));
  }
}

void GlContext::enableDebugOutput() {
  if (!epoxy_has_gl_extension("GL_KHR_debug") && epoxy_gl_version() < 43) return;
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS); // so a message's stack is the call's stack
  glDebugMessageCallback(reinterpret_cast<GLDEBUGPROC>(&GlContext::debugCallback), this);
  checkGlError("glDebugMessageCallback", __FILE__, __LINE__);
}

void GlContext::debugCallback(unsigned /*source*/, unsigned type, unsigned id, unsigned severity, int /*length*/, const char* message,
                              const void* self) {
  if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
  if (type == GL_DEBUG_TYPE_ERROR) ++const_cast<GlContext*>(static_cast<const GlContext*>(self))->debugErrors_;
  std::fprintf(stderr, "brushtrace: GL debug (id %u): %s\n", id, message);
}

} // namespace bt::gl
