// Compute programs built from the shaders embedded at build time (see CMakeLists.txt: the same
// files glslangValidator checked). Embedding, rather than reading shaders/ at run time, lets
// the binary be carried alone to another machine (scripts/gpu-check.sh).
#pragma once

#include "renderer/gl/gl_program_cache.h"

#include <chrono>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace bt::gl {

struct ShaderFile {
  const char* name; // file name in shaders/
  const char* source;
};

// Every file of shaders/, generated into the build by embed_shaders.cmake.
const std::vector<ShaderFile>& embeddedShaders();

// The GLSL text of shaders/<name> ready for glShaderSource: `#define`s for `defines` after
// #version, each `#include "x"` replaced by x's text between `#line` directives whose source
// number is x's index in embeddedShaders(), so a driver's "N:line" message names the file.
std::string assembleShader(std::string_view name, std::span<const std::string> defines);

// assembleShader's texts, each file's includes resolved once: the path tracer's kernels are one
// file under several define sets, and their starts are on the very first image's path.
class ShaderSources {
public:
  std::string assemble(std::string_view name, std::span<const std::string> defines);

private:
  struct File {
    std::string version; // the #version line
    std::string body;    // what follows the defines: the text after #version, its includes in place
  };
  std::map<std::string, File, std::less<>> files_;
};

// Whether `cache` has an entry for `source` (shaders/<name> as assembleShader or ShaderSources
// gave it) on the current context's driver, which ComputeProgram would load rather than compile
// (a file the driver then rejects is compiled after all). Reads no binary.
bool programCachedSource(std::string_view name, const std::string& source, const ProgramCache& cache);

// A linked compute program, loaded from `cache` when it holds a binary the driver accepts, else
// compiled (and stored there). Throws GlError with the driver's log, the source numbers
// translated to file names, when it does not compile or link.
//
// Building can be started and finished apart: with GL_KHR_parallel_shader_compile
// (GlContextInfo::parallelShaderCompile) glCompileShader and glLinkProgram return at once and
// the driver compiles on its own threads, so a program started before a level is imported is
// compiled while it loads. finish() waits for it, reports errors and fills the cache; every
// accessor below finishes first.
class ComputeProgram {
public:
  struct Deferred {};
  // Builds the program now.
  ComputeProgram(std::string_view name, std::span<const std::string> defines, const ProgramCache& cache = {});
  // Starts building it; finish() (or the first use) completes it.
  ComputeProgram(Deferred, std::string_view name, std::span<const std::string> defines, const ProgramCache& cache = {});
  // Starts building `source`, shaders/<name> as assembleShader (or ShaderSources) gave it.
  ComputeProgram(Deferred, std::string_view name, const std::string& source, const ProgramCache& cache = {});
  ~ComputeProgram();
  ComputeProgram(const ComputeProgram&) = delete;
  ComputeProgram& operator=(const ComputeProgram&) = delete;

  // Waits for the driver and checks the result; throws GlError as the constructor does.
  void finish();
  // Whether the driver's compile is done: asks the driver (GL_COMPLETION_STATUS_KHR) under
  // GL_KHR_parallel_shader_compile, and is true without it (glCompileShader and glLinkProgram
  // did the work in the constructor then). NVIDIA's finish() may still take a few tenths of a
  // second on the calling thread after this says done.
  bool ready();

  unsigned id() {
    finish();
    return program_;
  }
  // Wall time from the start of the build to finish(): glCompileShader + glLinkProgram (or
  // glProgramBinary when loaded from the cache), less whatever overlapped other work when the
  // build was started early. Drivers may defer part of the work to the first dispatch (Mesa's
  // llvmpipe does).
  double buildMilliseconds() {
    finish();
    return buildMilliseconds_;
  }
  bool loadedFromCache() const { return loadedFromCache_; }
  // The driver's binary of the finished program (glGetProgramBinary), as the cache stores it;
  // empty data where the driver gives none.
  ProgramBinary binary();
  // What the start cost its thread, in ms: all of it (the cache's key and look-up, the driver's
  // calls) and the driver's glShaderSource, glCompileShader and glLinkProgram alone. Under
  // GL_KHR_parallel_shader_compile these only queue the compile, yet NVIDIA's take a while.
  double startMilliseconds() const { return startMilliseconds_; }
  double startDriverMilliseconds() const { return startDriverMilliseconds_; }
  double startLinkMilliseconds() const { return startLinkMilliseconds_; } // of those, glLinkProgram
  // When the start returned: the compile queued.
  std::chrono::steady_clock::time_point queuedAt() const { return queued_; }
  // The program's local_size_x, _y or _z (axis 0, 1 or 2).
  int localSize(int axis) {
    finish();
    return localSize_[axis];
  }
  // Dispatches enough local_size_x by local_size_y groups to cover width by height invocations.
  void dispatch2d(int width, int height);

private:
  bool loadFrom(const ProgramBinary& binary);
  void startCompile(const std::string& source, bool retrievable);
  void finishCompile();
  ProgramBinary readBinary() const; // binary() once finished

  std::string name_;
  ProgramCache cache_;
  std::string cacheKey_;         // empty: not stored
  unsigned shader_ = 0;          // while a compile is in flight
  bool parallelCompile_ = false; // the driver compiles on its own threads (completion status)
  bool finished_ = false;
  std::string error_; // why the build failed, rethrown by every later finish()
  int localSize_[3] = {1, 1, 1};
  std::chrono::steady_clock::time_point start_, queued_;
  unsigned program_ = 0;
  double buildMilliseconds_ = 0.0;
  double startMilliseconds_ = 0.0, startDriverMilliseconds_ = 0.0, startLinkMilliseconds_ = 0.0;
  bool loadedFromCache_ = false;
};

} // namespace bt::gl
