// gl_compile_probe LEVEL EXPERIMENT [faithful|physical]: where a cold compile of the path tracer's
// programs spends its time on a driver that compiles on its own threads (issue 14's very first
// start). Run it with the driver's own cache off (NVIDIA: __GL_SHADER_DISK_CACHE=0), one
// experiment a process, so that nothing was compiled before.
//
// Programs (KIND): shade, trace, mega (the level's own wavefront shade kernel, trace kernel and
// megakernel), shade-bare (the shade kernel with no faithful parts), shade-lights and
// shade-surface (the shade kernel cut by hand in two: what a shadow ray's return and the next
// light need, and what a surface ray's return needs; measurement only, they draw nothing right).
// EXPERIMENT:
//   together:K1,K2,...  all started at once in that order on this thread; each one's driver
//                       compile polled to its end (GL_COMPLETION_STATUS_KHR), then each finished
//                       (GL_LINK_STATUS) in that order on this thread.
//   threads:K1,K2,...   started the same way, then each finished on its own thread with its own
//                       context of this context's share group, as soon as its compile is done.
//   dump:K              K's text as a GPU with bindless textures gets it, to stdout, no context:
//                       to edit by hand and compile as file=PATH (the text's variants need no
//                       build of the probe).
// A KIND file=PATH is the text in PATH (a dump, edited); spirv=PATH is a SPIR-V module for
// OpenGL (glslangValidator -G, maybe spirv-opt) given with glShaderBinary and glSpecializeShader
// (GL_ARB_gl_spirv): is the driver's compile of the same kernel shorter from SPIR-V? glslang
// compiles no bindless textures to SPIR-V, so its kernels are the arrays form (compare them
// with that form's text as file=PATH).
// Times in ms from the start of the compiles.
#include "importers/import.h"
#include "lighting/render_scene.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_level.h"
#include "renderer/gl/gl_lighting.h"
#include "renderer/gl/gl_program.h"
#include "renderer/gl/gl_tracer_programs.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <fmt/format.h>

#include <chrono>
#include <fstream>
#include <iterator>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  if (at == std::string::npos) throw std::runtime_error("probe: text not found: " + from);
  return text.replace(at, from.size(), to);
}

bool isSpirv(const std::string& kind) {
  return kind.starts_with("spirv=");
}

std::string fileText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("probe: cannot read " + path);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::string sourceFor(const std::string& kind, bool physical, bt::gl::FaithfulFeatures features, uint32_t nonce,
                      const bt::gl::GlContextInfo& info) {
  using namespace bt::gl;
  const TextureMode mode = info.bindlessTextures ? TextureMode::Bindless : TextureMode::Arrays;
  const TraceLayout layout = info.softwareRenderer ? TraceLayout::Software : TraceLayout::Hardware;
  std::string text;
  if (kind.starts_with("file=")) {
    text = fileText(kind.substr(5));
  } else if (isSpirv(kind)) {
    return fileText(kind.substr(6)); // a binary no driver has seen in this process; no nonce
  } else if (kind == "trace")
    text = assembleShader("wavefront_trace.comp", programDefines(TracerProgram::WavefrontTrace, mode, layout));
  else if (kind == "mega")
    text = assembleShader("pathtrace.comp", programDefines(TracerProgram::PathTracer, mode, layout, physical, features));
  else {
    FaithfulFeatures f = features;
    if (kind == "shade-bare") f = FaithfulFeatures{.liquidCsg = features.liquidCsg};
    text = assembleShader("pathtrace.comp", programDefines(TracerProgram::WavefrontShade, mode, layout, physical, f));
    if (kind == "shade-lights") {
      text = replaced(text, "bool shadowPassed = path.kind == RAY_SHADOW && hit.face == NO_FACE;\n  if (path.kind == RAY_SHADOW) {",
                      "bool shadowPassed = hit.face == NO_FACE;\n  if (true) {");
    } else if (kind == "shade-surface") {
      text = replaced(text, "if (nextLightRay(path, rng)) return true;", "");
      text = replaced(text, "faithfulPathEnd(path, rng) ||", "");
      text = replaced(text, "bool shadowPassed = path.kind == RAY_SHADOW && hit.face == NO_FACE;\n  if (path.kind == RAY_SHADOW) {",
                      "bool shadowPassed = false;\n  if (false) {");
    } else if (kind != "shade") {
      throw std::runtime_error("probe: no program " + kind);
    }
  }
  // A text no driver has seen, whatever it keeps in memory (none in a dump).
  if (nonce == 0) return text;
  return replaced(text, "\n", fmt::format("\n#define BT_PROBE_NONCE {}u\n", nonce));
}

struct Probe {
  std::string kind;
  GLuint shader = 0, program = 0;
  double started = 0, specialized = -1, compiled = -1, finishStart = 0, finished = 0;
  int ok = 0;
};

void start(Probe& p, const std::string& source, Clock::time_point t0) {
  p.started = msSince(t0);
  p.shader = glCreateShader(GL_COMPUTE_SHADER);
  if (isSpirv(p.kind)) {
    // The driver compiles a SPIR-V module at glSpecializeShader, before the link.
    glShaderBinary(1, &p.shader, GL_SHADER_BINARY_FORMAT_SPIR_V_ARB, source.data(), GLsizei(source.size()));
    glSpecializeShaderARB(p.shader, "main", 0, nullptr, nullptr);
    p.specialized = msSince(t0);
  } else {
    const char* text = source.c_str();
    glShaderSource(p.shader, 1, &text, nullptr);
    glCompileShader(p.shader);
  }
  p.program = glCreateProgram();
  glAttachShader(p.program, p.shader);
  glLinkProgram(p.program);
}

bool done(Probe& p) {
  GLint status = GL_TRUE;
  glGetProgramiv(p.program, GL_COMPLETION_STATUS_KHR, &status);
  return status == GL_TRUE;
}

void finish(Probe& p, Clock::time_point t0) {
  p.finishStart = msSince(t0);
  GLint compiled = 0;
  glGetShaderiv(p.shader, GL_COMPILE_STATUS, &compiled);
  glGetProgramiv(p.program, GL_LINK_STATUS, &p.ok);
  p.ok = p.ok && compiled;
  p.finished = msSince(t0);
  if (!p.ok) {
    char log[4096] = {};
    glGetShaderInfoLog(p.shader, sizeof log, nullptr, log);
    fmt::print("{}: {}\n", p.kind, log);
  }
}

// Polls every program's completion until all are done (a thread of its own per program in
// `threads` mode does it there instead).
void pollAll(std::vector<Probe>& probes, Clock::time_point t0) {
  for (;;) {
    bool all = true;
    for (Probe& p : probes) {
      if (p.compiled < 0 && done(p)) p.compiled = msSince(t0);
      all = all && p.compiled >= 0;
    }
    if (all) return;
    std::this_thread::sleep_for(std::chrono::microseconds(250));
  }
}

} // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: gl_compile_probe LEVEL together:K1,K2,...|threads:K1,K2,... [faithful|physical]\n");
    return 2;
  }
  const bool physical = argc > 3 && std::string(argv[3]) == "physical";
  const std::string experiment = argv[2];
  const size_t colon = experiment.find(':');
  const std::string how = experiment.substr(0, colon);
  std::vector<std::string> kinds;
  {
    std::istringstream list(experiment.substr(colon + 1));
    for (std::string k; std::getline(list, k, ',');) kinds.push_back(k);
  }
  try {
    // The level's own features, as loadGlLevel finds them.
    bt::Scene scene = bt::importScene(argv[1], {});
    bt::RenderScene render = bt::buildRenderScene(scene, bt::gl::glSceneOptions(), scene.diagnostics);
    const bt::gl::FaithfulFeatures features = bt::gl::faithfulFeatures(bt::gl::lightingFor(render));
    if (how == "dump") {
      bt::gl::GlContextInfo gpu;
      gpu.bindlessTextures = true;
      fmt::print("{}", sourceFor(kinds.at(0), physical, features, 0, gpu));
      return 0;
    }
    fmt::print("features: dirt {} bounceDraw {} sky {} jitter {} negative {} filter {} liquidCsg {} inside {} glass {}\n", features.dirt,
               features.bounceDraw, features.sky, features.jitter, features.negative, features.filter, features.liquidCsg,
               features.blocksFromInside, features.glass);

    auto contextStart = Clock::now();
    auto context = bt::gl::GlContext::createHeadless();
    fmt::print("context: {:.1f} ms, {}, GL_ARB_gl_spirv {}\n", msSince(contextStart), context->info().renderer,
               epoxy_has_gl_extension("GL_ARB_gl_spirv"));
    const uint32_t nonce = std::random_device{}() | 1u;
    std::vector<std::string> sources;
    for (const std::string& k : kinds) sources.push_back(sourceFor(k, physical, features, nonce, context->info()));

    std::vector<Probe> probes(kinds.size());
    const auto t0 = Clock::now();
    for (size_t i = 0; i < kinds.size(); ++i) probes[i].kind = kinds[i], start(probes[i], sources[i], t0);
    if (how == "together") {
      pollAll(probes, t0);
      for (Probe& p : probes) finish(p, t0);
    } else if (how == "threads") {
      const EGLDisplay display = eglGetCurrentDisplay();
      const EGLContext shared = eglGetCurrentContext();
      glFlush(); // the programs exist for the other contexts
      std::vector<std::thread> threads;
      for (Probe& p : probes)
        threads.emplace_back([&, display, shared] {
          const EGLint attribs[] = {
              EGL_CONTEXT_MAJOR_VERSION,           4,       EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
              EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
          eglBindAPI(EGL_OPENGL_API);
          const EGLContext own = eglCreateContext(display, EGL_NO_CONFIG_KHR, shared, attribs);
          if (own == EGL_NO_CONTEXT || !eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, own)) {
            fmt::print("{}: no shared context (EGL 0x{:04x})\n", p.kind, eglGetError());
            return;
          }
          while (!done(p)) std::this_thread::sleep_for(std::chrono::microseconds(250));
          p.compiled = msSince(t0);
          finish(p, t0);
          eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
          eglDestroyContext(display, own);
        });
      for (std::thread& t : threads) t.join();
    } else {
      throw std::runtime_error("probe: no experiment " + how);
    }
    for (const Probe& p : probes)
      fmt::print("{:<14} {:>7} chars: started {:6.1f}, compiled {:6.1f}, finish {:6.1f} -> {:6.1f} ({:5.1f} ms){}\n", p.kind,
                 sources[size_t(&p - probes.data())].size(), p.started, p.compiled, p.finishStart, p.finished, p.finished - p.finishStart,
                 p.ok ? "" : " FAILED");
    for (const Probe& p : probes)
      if (p.specialized >= 0) fmt::print("{}: glSpecializeShader returned at {:.1f} ms\n", p.kind, p.specialized);
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "gl_compile_probe: {}\n", e.what());
    return 1;
  }
}
