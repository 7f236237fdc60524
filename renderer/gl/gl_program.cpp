#include "renderer/gl/gl_program.h"

#include "renderer/gl/gl_error.h"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
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

namespace {

// shaders/<name>'s #version line, and the rest with its includes in place (assembleShader).
std::pair<std::string, std::string> assembleFile(std::string_view name) {
  const size_t root = shaderIndex(name);
  const std::string_view source = embeddedShaders()[root].source;
  const size_t versionEnd = source.find('\n');
  if (!source.starts_with("#version") || versionEnd == std::string::npos)
    throw GlError(fmt::format("shader '{}' does not start with #version", name));
  std::string text;
  std::set<size_t> included{root};
  // appendFile reads the root from the top; its #version line is dropped afterwards.
  appendFile(text, root, included);
  return {std::string(source.substr(0, versionEnd + 1)), fmt::format("#line 2 {}\n", root) + text.substr(text.find('\n') + 1)};
}

std::string withDefines(const std::string& version, const std::string& body, std::span<const std::string> defines) {
  std::string out = version;
  for (const auto& d : defines) out += "#define " + d + "\n";
  out += body;
  return out;
}

} // namespace

std::string assembleShader(std::string_view name, std::span<const std::string> defines) {
  const auto [version, body] = assembleFile(name);
  return withDefines(version, body, defines);
}

std::string ShaderSources::assemble(std::string_view name, std::span<const std::string> defines) {
  auto it = files_.find(name);
  if (it == files_.end()) {
    auto [version, body] = assembleFile(name);
    it = files_.emplace(std::string(name), File{std::move(version), std::move(body)}).first;
  }
  return withDefines(it->second.version, it->second.body, defines);
}

namespace {

std::string glString(GLenum name) {
  const auto* text = reinterpret_cast<const char*>(glGetString(name));
  return text ? text : "";
}

// The binary formats the driver can load; none means the cache has nothing to offer.
std::vector<GLint> programBinaryFormats() {
  GLint count = 0;
  glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &count);
  std::vector<GLint> formats(static_cast<size_t>(std::max(count, 0)));
  if (count > 0) glGetIntegerv(GL_PROGRAM_BINARY_FORMATS, formats.data());
  return formats;
}

bool isOpaqueType(GLint type) {
  switch (type) {
  case GL_SAMPLER_2D:
  case GL_SAMPLER_2D_ARRAY:
  case GL_INT_SAMPLER_2D:
  case GL_UNSIGNED_INT_SAMPLER_2D:
  case GL_IMAGE_2D:
  case GL_INT_IMAGE_2D:
  case GL_UNSIGNED_INT_IMAGE_2D:
  case GL_IMAGE_2D_ARRAY:
  case GL_UNSIGNED_INT_IMAGE_2D_ARRAY: return true;
  default: return false;
  }
}

// Every binding point the linked program has: sampler and image units (each array element),
// and the buffer binding of each storage and uniform block.
std::vector<ProgramBindingPoint> readBindings(GLuint program) {
  std::vector<ProgramBindingPoint> out;
  GLint count = 0;
  glGetProgramInterfaceiv(program, GL_UNIFORM, GL_ACTIVE_RESOURCES, &count);
  for (GLint i = 0; i < count; ++i) {
    const GLenum props[] = {GL_TYPE, GL_ARRAY_SIZE, GL_BLOCK_INDEX, GL_NAME_LENGTH};
    GLint values[4] = {};
    glGetProgramResourceiv(program, GL_UNIFORM, static_cast<GLuint>(i), 4, props, 4, nullptr, values);
    if (values[2] != -1 || !isOpaqueType(values[0])) continue;
    std::string name(static_cast<size_t>(std::max(values[3], 1)), '\0');
    glGetProgramResourceName(program, GL_UNIFORM, static_cast<GLuint>(i), values[3], nullptr, name.data());
    name.resize(std::strlen(name.c_str()));
    if (name.ends_with("[0]")) name.resize(name.size() - 3);
    for (GLint element = 0; element < std::max(values[1], 1); ++element) {
      const std::string elementName = values[1] > 1 ? fmt::format("{}[{}]", name, element) : name;
      const GLint location = glGetProgramResourceLocation(program, GL_UNIFORM, elementName.c_str());
      if (location < 0) continue;
      GLint unit = 0;
      glGetUniformiv(program, location, &unit);
      out.push_back({ProgramBindingPoint::Uniform, location, unit});
    }
  }
  for (const auto& [interface, kind] : {std::pair{GL_SHADER_STORAGE_BLOCK, ProgramBindingPoint::StorageBlock},
                                        std::pair{GL_UNIFORM_BLOCK, ProgramBindingPoint::UniformBlock}}) {
    glGetProgramInterfaceiv(program, interface, GL_ACTIVE_RESOURCES, &count);
    for (GLint i = 0; i < count; ++i) {
      const GLenum prop = GL_BUFFER_BINDING;
      GLint binding = 0;
      glGetProgramResourceiv(program, interface, static_cast<GLuint>(i), 1, &prop, 1, nullptr, &binding);
      out.push_back({kind, i, binding});
    }
  }
  checkGlError("reading a program's binding points", __FILE__, __LINE__);
  return out;
}

void applyBindings(GLuint program, const std::vector<ProgramBindingPoint>& bindings) {
  for (const ProgramBindingPoint& b : bindings) {
    switch (b.kind) {
    case ProgramBindingPoint::Uniform: glProgramUniform1i(program, b.index, b.binding); break;
    case ProgramBindingPoint::StorageBlock:
      glShaderStorageBlockBinding(program, static_cast<GLuint>(b.index), static_cast<GLuint>(b.binding));
      break;
    case ProgramBindingPoint::UniformBlock:
      glUniformBlockBinding(program, static_cast<GLuint>(b.index), static_cast<GLuint>(b.binding));
      break;
    }
  }
  checkGlError("restoring a cached program's binding points", __FILE__, __LINE__);
}

} // namespace

bool programCachedSource(std::string_view name, const std::string& source, const ProgramCache& cache) {
  if (!cache.enabled() || programBinaryFormats().empty()) return false;
  const std::string key = programCacheKey(source, glString(GL_VENDOR), glString(GL_RENDERER), glString(GL_VERSION));
  std::error_code ignored;
  return std::filesystem::exists(cache.fileFor(name, key), ignored);
}

ComputeProgram::ComputeProgram(std::string_view name, std::span<const std::string> defines, const ProgramCache& cache)
    : ComputeProgram(Deferred{}, name, defines, cache) {
  finish();
}

ComputeProgram::ComputeProgram(Deferred, std::string_view name, std::span<const std::string> defines, const ProgramCache& cache)
    : ComputeProgram(Deferred{}, name, assembleShader(name, defines), cache) {}

ComputeProgram::ComputeProgram(Deferred, std::string_view name, const std::string& source, const ProgramCache& cache) : name_(name) {
  using Clock = std::chrono::steady_clock;
  const auto entered = Clock::now();
  const bool useCache = cache.enabled() && !programBinaryFormats().empty();
  if (useCache) {
    cache_ = cache;
    cacheKey_ = programCacheKey(source, glString(GL_VENDOR), glString(GL_RENDERER), glString(GL_VERSION));
  }
  parallelCompile_ = epoxy_has_gl_extension("GL_KHR_parallel_shader_compile") || epoxy_has_gl_extension("GL_ARB_parallel_shader_compile");
  start_ = Clock::now();
  if (useCache) {
    if (const std::optional<ProgramBinary> binary = cache.load(name, cacheKey_)) loadedFromCache_ = loadFrom(*binary);
  }
  const auto compileCalled = Clock::now();
  if (!loadedFromCache_) startCompile(source, useCache);
  queued_ = Clock::now();
  startMilliseconds_ = std::chrono::duration<double, std::milli>(queued_ - entered).count();
  startDriverMilliseconds_ = std::chrono::duration<double, std::milli>(queued_ - compileCalled).count();
}

void ComputeProgram::finish() {
  if (!error_.empty()) throw GlError(error_); // a failed build stays failed
  if (finished_) return;
  finished_ = true;
  try {
    if (!loadedFromCache_) finishCompile();
  } catch (const GlError& e) {
    error_ = e.what();
    throw;
  }
  buildMilliseconds_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  if (!cacheKey_.empty() && !loadedFromCache_) cache_.store(name_, cacheKey_, readBinary());
  BT_GL(glGetProgramiv(program_, GL_COMPUTE_WORK_GROUP_SIZE, localSize_));
}

ProgramBinary ComputeProgram::binary() {
  finish();
  return readBinary();
}

ProgramBinary ComputeProgram::readBinary() const {
  GLint length = 0;
  BT_GL(glGetProgramiv(program_, GL_PROGRAM_BINARY_LENGTH, &length));
  ProgramBinary binary;
  binary.data.resize(static_cast<size_t>(std::max(length, 0)));
  GLenum format = 0;
  GLsizei written = 0;
  if (length > 0) BT_GL(glGetProgramBinary(program_, length, &written, &format, binary.data.data()));
  binary.data.resize(static_cast<size_t>(std::max(written, 0)));
  binary.format = format;
  binary.bindings = readBindings(program_);
  return binary;
}

bool ComputeProgram::ready() {
  if (finished_ || loadedFromCache_ || !error_.empty() || !parallelCompile_) return true;
  GLint done = GL_TRUE;
  glGetProgramiv(program_, GL_COMPLETION_STATUS_KHR, &done); // GL_COMPLETION_STATUS_ARB is the same enum
  return done == GL_TRUE;
}

// A binary the driver rejects (another driver build, a corrupt file) leaves the link status
// false without a GL error; the caller then compiles from source.
bool ComputeProgram::loadFrom(const ProgramBinary& binary) {
  const std::vector<GLint> formats = programBinaryFormats();
  if (std::find(formats.begin(), formats.end(), static_cast<GLint>(binary.format)) == formats.end()) return false;
  program_ = glCreateProgram();
  glProgramBinary(program_, binary.format, binary.data.data(), static_cast<GLsizei>(binary.data.size()));
  GLint ok = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (ok) {
    applyBindings(program_, binary.bindings);
    return true;
  }
  glDeleteProgram(program_);
  program_ = 0;
  return false;
}

// Under GL_KHR_parallel_shader_compile both calls only queue the work; finishCompile's status
// queries are where the caller waits.
void ComputeProgram::startCompile(const std::string& source, bool retrievable) {
  shader_ = glCreateShader(GL_COMPUTE_SHADER);
  const char* text = source.c_str();
  glShaderSource(shader_, 1, &text, nullptr);
  glCompileShader(shader_);
  program_ = glCreateProgram();
  if (retrievable) glProgramParameteri(program_, GL_PROGRAM_BINARY_RETRIEVABLE_HINT, GL_TRUE);
  glAttachShader(program_, shader_);
  const auto linkCalled = std::chrono::steady_clock::now();
  glLinkProgram(program_);
  startLinkMilliseconds_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - linkCalled).count();
  checkGlError("starting a program's compile", __FILE__, __LINE__);
}

void ComputeProgram::finishCompile() {
  const GLuint shader = shader_;
  shader_ = 0;
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    glDeleteShader(shader);
    glDeleteProgram(program_);
    program_ = 0;
    throw GlError(fmt::format("{} does not compile ({}):\n{}", name_, sourceLegend(), log.c_str()));
  }
  glDetachShader(program_, shader);
  glDeleteShader(shader);
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(program_, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program_, length, nullptr, log.data());
    glDeleteProgram(program_);
    program_ = 0;
    throw GlError(fmt::format("{} does not link:\n{}", name_, log.c_str()));
  }
}

ComputeProgram::~ComputeProgram() {
  if (shader_) glDeleteShader(shader_);
  if (program_) glDeleteProgram(program_);
}

void ComputeProgram::dispatch2d(int width, int height) {
  finish();
  BT_GL(glUseProgram(program_));
  const auto groups = [](int n, int size) { return static_cast<GLuint>((n + size - 1) / size); };
  BT_GL(glDispatchCompute(groups(width, localSize_[0]), groups(height, localSize_[1]), 1));
}

} // namespace bt::gl
