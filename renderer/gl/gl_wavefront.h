// The wavefront form's per-pixel state (shaders/wavefront.glsl) and its dispatch loop: the ray
// each path waits for, its hit, the path itself, and the count of paths ended.
#pragma once

#include <cstddef>
#include <cstdint>

namespace bt::gl {

class ComputeProgram;
struct PixelRect;

// Sized for the largest image drawn so far; the struct strides are the shade kernel's (std430,
// read from the program).
class WavefrontBuffers {
public:
  WavefrontBuffers() = default;
  ~WavefrontBuffers();
  WavefrontBuffers(const WavefrontBuffers&) = delete;
  WavefrontBuffers& operator=(const WavefrontBuffers&) = delete;

  void prepare(ComputeProgram& shade, int width, int height);
  // Gives the memory back (at 1280x720 some 300 MB) once the megakernel draws.
  void release();
  void bind() const;

  // One sample (camera, world, scene and the image at unit 0 bound) of the pixels of `piece`,
  // a rectangle of the width x height image that starts where the camera block's pixelOffset
  // says: the shade kernel starts each of its pixels' paths at the camera, then trace and shade
  // by turns until every path has ended; each adds its sample to the image as it ends.
  void drawSample(ComputeProgram& shade, ComputeProgram& trace, int width, int height, const PixelRect& piece);

private:
  struct Buffer {
    unsigned id = 0;
    size_t bytes = 0;
  };

  void clearEndedCount() const;
  uint32_t endedCount() const;
  static size_t arrayStride(unsigned program, const char* member);
  static void reserve(Buffer& b, size_t bytes);

  Buffer buffers_[4]; // rays, hits, paths, ended count
  unsigned readBack_ = 0;
};

} // namespace bt::gl
