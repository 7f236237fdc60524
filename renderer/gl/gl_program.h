// Compute programs built from the shaders embedded at build time (see CMakeLists.txt: the same
// files glslangValidator checked). Embedding, rather than reading shaders/ at run time, lets
// the binary be carried alone to another machine (scripts/gpu-check.sh).
#pragma once

#include "renderer/gl/gl_program_cache.h"

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace bt::gl {

struct ShaderFile {
  const char* name;   // file name in shaders/
  const char* source;
};

// Every file of shaders/, generated into the build by embed_shaders.cmake.
const std::vector<ShaderFile>& embeddedShaders();

// The GLSL text of shaders/<name> ready for glShaderSource: `#define`s for `defines` after
// #version, each `#include "x"` replaced by x's text between `#line` directives whose source
// number is x's index in embeddedShaders(), so a driver's "N:line" message names the file.
std::string assembleShader(std::string_view name, std::span<const std::string> defines);

// A linked compute program, loaded from `cache` when it holds a binary the driver accepts, else
// compiled (and stored there). Throws GlError with the driver's log, the source numbers
// translated to file names, when it does not compile or link.
class ComputeProgram {
public:
  ComputeProgram(std::string_view name, std::span<const std::string> defines, const ProgramCache& cache = {});
  ~ComputeProgram();
  ComputeProgram(const ComputeProgram&) = delete;
  ComputeProgram& operator=(const ComputeProgram&) = delete;

  unsigned id() const { return program_; }
  // Wall time of glCompileShader + glLinkProgram, or of glProgramBinary when loaded from the
  // cache. Drivers may defer part of the work to the first dispatch (Mesa's llvmpipe does).
  double buildMilliseconds() const { return buildMilliseconds_; }
  bool loadedFromCache() const { return loadedFromCache_; }
  // Dispatches enough local_size_x by local_size_y groups to cover width by height invocations.
  void dispatch2d(int width, int height) const;

private:
  bool loadFrom(const ProgramBinary& binary);
  void compile(std::string_view name, const std::string& source, bool retrievable);

  unsigned program_ = 0;
  int localSize_[3] = {1, 1, 1};
  double buildMilliseconds_ = 0.0;
  bool loadedFromCache_ = false;
};

} // namespace bt::gl
