#include "bvh/trace_scene.h"

#include <cmath>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace bt {
namespace {

// One axis of GL_LINEAR + GL_REPEAT (OpenGL 4.6 core, 8.14.2 and 8.14.3): the coordinate in
// texels is u * size - 0.5, the two texels are floor of that and the next one, wrapped with
// repeat, and the weight of the second is the fraction. The repeat is taken on u first (in
// double), which is what keeps far-away texture coordinates as precise as ones near 0.
struct LinearTaps {
  int first, second;
  double weight; // of `second`
};

LinearTaps linearTaps(float coordinate, int size) {
  double u = std::isfinite(coordinate) ? static_cast<double>(coordinate) : 0.0;
  u -= std::floor(u); // [0, 1)
  const double x = u * size - 0.5;
  const double base = std::floor(x); // -1 .. size - 1
  int first = static_cast<int>(base);
  int second = first + 1;
  if (first < 0) first += size;
  if (second >= size) second -= size;
  return {first, second, x - base};
}

#if defined(__SSE2__)
// A texel's four bytes over 255, one SSE lane a channel: the scalar form's floats (a byte
// converts exactly, then the same multiply). The physical tracer fetches four of these a hit,
// and as calls they cost more than their loads.
inline __m128 texelValue(const Image& image, int x, int y) {
  uint32_t bytes;
  std::memcpy(&bytes, image.texel(x, y), 4);
  const __m128i zero = _mm_setzero_si128();
  const __m128i words = _mm_unpacklo_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(int(bytes)), zero), zero);
  return _mm_mul_ps(_mm_cvtepi32_ps(words), _mm_set1_ps(1.0f / 255.0f));
}
#else
glm::vec4 texelValue(const Image& image, int x, int y) {
  const uint8_t* t = image.texel(x, y);
  return glm::vec4(t[0], t[1], t[2], t[3]) * (1.0f / 255.0f);
}
#endif

} // namespace

glm::vec4 sampleBilinearRepeat(const Image& image, float u, float v) {
  if (image.empty() || image.rgba.size() < static_cast<size_t>(image.width) * image.height * 4) return glm::vec4(0.0f);
  const LinearTaps x = linearTaps(u, image.width);
  const LinearTaps y = linearTaps(v, image.height);
  const float wx = static_cast<float>(x.weight), wy = static_cast<float>(y.weight);
#if defined(__SSE2__)
  // The scalar form's expressions lane by lane, in its order.
  const auto lerp = [](__m128 a, __m128 b, float w) {
    return _mm_add_ps(_mm_mul_ps(a, _mm_set1_ps(1.0f - w)), _mm_mul_ps(b, _mm_set1_ps(w)));
  };
  const __m128 top = lerp(texelValue(image, x.first, y.first), texelValue(image, x.second, y.first), wx);
  const __m128 bottom = lerp(texelValue(image, x.first, y.second), texelValue(image, x.second, y.second), wx);
  glm::vec4 out;
  _mm_storeu_ps(&out.x, lerp(top, bottom, wy));
  return out;
#else
  const glm::vec4 top = texelValue(image, x.first, y.first) * (1.0f - wx) + texelValue(image, x.second, y.first) * wx;
  const glm::vec4 bottom = texelValue(image, x.first, y.second) * (1.0f - wx) + texelValue(image, x.second, y.second) * wx;
  return top * (1.0f - wy) + bottom * wy;
#endif
}

} // namespace bt
