#include "renderer/gl/gl_error.h"

#include <epoxy/gl.h>
#include <fmt/format.h>

namespace bt::gl {

const char* glErrorName(unsigned error) {
  switch (error) {
  case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
  case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
  case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
  case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
  case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
  case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
  case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
  default: return "unknown GL error";
  }
}

void checkGlError(const char* call, const char* file, int line) {
  GLenum error = glGetError();
  if (error == GL_NO_ERROR) return;
  std::string text = fmt::format("{}:{}: {} failed with {}", file, line, call, glErrorName(error));
  // glGetError keeps a queue of flags; drain it so the next check names only its own call.
  while ((error = glGetError()) != GL_NO_ERROR) text += fmt::format(", {}", glErrorName(error));
  throw GlError(text);
}

} // namespace bt::gl
