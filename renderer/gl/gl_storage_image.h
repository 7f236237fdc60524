// The images the tracer's kernels write, and their read-back to the CPU. Included by the
// tracer's own sources only: it needs GL's enums.
#pragma once

#include "renderer/gl/gl_error.h"

#include <epoxy/gl.h>

#include <span>
#include <vector>

namespace bt::gl {

// An RGBA32F or R32UI image the shaders write, deleted with its owner.
class StorageImage {
public:
  StorageImage(GLenum format, int width, int height) : format_(format) {
    BT_GL(glCreateTextures(GL_TEXTURE_2D, 1, &texture_));
    BT_GL(glTextureStorage2D(texture_, 1, format, width, height));
  }
  ~StorageImage() { glDeleteTextures(1, &texture_); }
  StorageImage(const StorageImage&) = delete;
  StorageImage& operator=(const StorageImage&) = delete;

  void bindImage(GLuint unit, GLenum access) const { BT_GL(glBindImageTexture(unit, texture_, 0, GL_FALSE, 0, access, format_)); }

  // Hands `use` the image's pixels (width * height * components values of T, top row first as
  // the shaders write them), valid during the call. They come through a pixel-pack buffer that
  // the driver fills by a GPU copy and that is then mapped: NVIDIA's glGetTextureImage into
  // client memory is far slower than the bus (bench/README.md); a buffer copy runs at bus speed.
  template <typename T, typename Use>
  void readMapped(int width, int height, GLenum pixelFormat, GLenum type, int components, const Use& use) const {
    const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(components);
    const GLsizeiptr bytes = static_cast<GLsizeiptr>(count * sizeof(T));
    GLuint buffer = 0;
    BT_GL(glCreateBuffers(1, &buffer));
    struct Deleter {
      GLuint id;
      ~Deleter() { glDeleteBuffers(1, &id); }
    } deleter{buffer};
    // Client storage: the driver keeps the copy in host memory, where mapping it costs nothing.
    BT_GL(glNamedBufferStorage(buffer, bytes, nullptr, GL_MAP_READ_BIT | GL_CLIENT_STORAGE_BIT));
    BT_GL(glBindBuffer(GL_PIXEL_PACK_BUFFER, buffer));
    glGetTextureImage(texture_, 0, pixelFormat, type, static_cast<GLsizei>(bytes), nullptr); // offset 0 in the buffer
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0); // unbound before any error is thrown: other reads use client memory
    checkGlError("glGetTextureImage", __FILE__, __LINE__);
    const void* mapped = glMapNamedBufferRange(buffer, 0, bytes, GL_MAP_READ_BIT);
    if (!mapped) {
      checkGlError("glMapNamedBufferRange", __FILE__, __LINE__);
      throw GlError("glMapNamedBufferRange returned no memory for the image read back");
    }
    struct Unmapper {
      GLuint id;
      ~Unmapper() { glUnmapNamedBuffer(id); }
    } unmapper{buffer};
    use(std::span<const T>(static_cast<const T*>(mapped), count));
  }

  template <typename T> std::vector<T> read(int width, int height, GLenum pixelFormat, GLenum type, int components) const {
    std::vector<T> pixels;
    readMapped<T>(width, height, pixelFormat, type, components,
                  [&](std::span<const T> mapped) { pixels.assign(mapped.begin(), mapped.end()); });
    return pixels;
  }

private:
  GLenum format_;
  GLuint texture_ = 0;
};

} // namespace bt::gl
