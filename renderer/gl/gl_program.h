// Compute programs built from the shaders embedded at build time (see CMakeLists.txt: the same
// files glslangValidator checked). Embedding, rather than reading shaders/ at run time, lets
// the binary be carried alone to another machine (scripts/gpu-check.sh).
#pragma once

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

// A linked compute program. Throws GlError with the driver's log, the source numbers
// translated to file names, when it does not compile or link.
class ComputeProgram {
public:
  ComputeProgram(std::string_view name, std::span<const std::string> defines);
  ~ComputeProgram();
  ComputeProgram(const ComputeProgram&) = delete;
  ComputeProgram& operator=(const ComputeProgram&) = delete;

  unsigned id() const { return program_; }
  // Dispatches enough local_size_x by local_size_y groups to cover width by height invocations.
  void dispatch2d(int width, int height) const;

private:
  unsigned program_ = 0;
  int localSize_[3] = {1, 1, 1};
};

} // namespace bt::gl
