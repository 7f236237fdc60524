#include "renderer/gl/gl_program.h"

#include "renderer/gl/gl_error.h"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include <set>
#include <sstream>

namespace bt::gl {

namespace {

size_t shaderIndex(std::string_view name) {
  const auto& files = embeddedShaders();
  for (size_t i = 0; i < files.size(); ++i)
    if (name == files[i].name) return i;
  throw GlError(fmt::format("shader '{}' is not among the embedded shaders", name));
}

void appendFile(std::string& out, size_t index, std::set<size_t>& included) {
  included.insert(index);
  std::istringstream in(embeddedShaders()[index].source);
  std::string line;
  int lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    if (line.starts_with("#extension GL_GOOGLE_include_directive")) {
      out += "\n"; // glslangValidator's include extension; drivers resolve nothing themselves
      continue;
    }
    if (line.starts_with("#include \"")) {
      const size_t end = line.find('"', 10);
      const size_t child = shaderIndex(line.substr(10, end == std::string::npos ? std::string::npos : end - 10));
      if (!included.count(child)) {
        out += fmt::format("#line 1 {}\n", child);
        appendFile(out, child, included);
      }
      out += fmt::format("#line {} {}\n", lineNumber + 1, index);
      continue;
    }
    out += line;
    out += '\n';
  }
}

std::string sourceLegend() {
  std::string text = "source numbers:";
  const auto& files = embeddedShaders();
  for (size_t i = 0; i < files.size(); ++i) text += fmt::format(" {}={}", i, files[i].name);
  return text;
}

} // namespace

std::string assembleShader(std::string_view name, std::span<const std::string> defines) {
  const size_t root = shaderIndex(name);
  std::string source = embeddedShaders()[root].source;
  const size_t versionEnd = source.find('\n');
  if (!source.starts_with("#version") || versionEnd == std::string::npos)
    throw GlError(fmt::format("shader '{}' does not start with #version", name));

  std::string out = source.substr(0, versionEnd + 1);
  for (const auto& d : defines) out += "#define " + d + "\n";
  out += fmt::format("#line 2 {}\n", root);
  std::string body;
  std::set<size_t> included{root};
  // appendFile re-reads the root from the top; drop its #version line afterwards.
  appendFile(body, root, included);
  out += body.substr(body.find('\n') + 1);
  return out;
}

ComputeProgram::ComputeProgram(std::string_view name, std::span<const std::string> defines) {
  const std::string source = assembleShader(name, defines);
  const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    glDeleteShader(shader);
    throw GlError(fmt::format("{} does not compile ({}):\n{}", name, sourceLegend(), log.c_str()));
  }
  program_ = glCreateProgram();
  glAttachShader(program_, shader);
  glLinkProgram(program_);
  glDeleteShader(shader);
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(program_, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program_, length, nullptr, log.data());
    glDeleteProgram(program_);
    throw GlError(fmt::format("{} does not link:\n{}", name, log.c_str()));
  }
  BT_GL(glGetProgramiv(program_, GL_COMPUTE_WORK_GROUP_SIZE, localSize_));
}

ComputeProgram::~ComputeProgram() {
  if (program_) glDeleteProgram(program_);
}

void ComputeProgram::dispatch2d(int width, int height) const {
  BT_GL(glUseProgram(program_));
  const auto groups = [](int n, int size) { return static_cast<GLuint>((n + size - 1) / size); };
  BT_GL(glDispatchCompute(groups(width, localSize_[0]), groups(height, localSize_[1]), 1));
}

} // namespace bt::gl
