// The pinhole camera, set by renderer/gl/gl_tracer.cpp from a bt::gl::CameraBasis.
// right and up are scaled so that pixel centres span the image: a ray through pixel (x, y),
// y counted from the top row, has direction forward + (2 (x / w) - 1) right + (1 - 2 (y / h)) up.
#include "gl_bindings.glsl"
layout(std140, binding = BT_UNIFORM_CAMERA) uniform Camera {
  vec3 origin;
  float pad0;
  vec3 forward; // unit
  float pad1;
  vec3 right;   // tan(fovX / 2) long
  float pad2;
  vec3 up;      // tan(fovY / 2) long
  float pad3;
  ivec2 imageSize;
  uint frameIndex;   // the sample index this dispatch takes (pixelRng's sample number)
  uint seed;
  uint firstFrame;   // frameIndex of the first sample of this accumulation: it clears the sum
  uint pad4;
  ivec2 pixelOffset; // the top-left pixel of the piece of the image a dispatch draws; (0, 0): all of it
} camera;

// The pixel of this invocation. A slow GL draws a sample in pieces (renderer/gl/gl_progressive.h),
// a dispatch each, whose offsets are multiples of the work group size: the groups of one piece end
// where the next begins, or at the image's edge, and need no bound of their own.
ivec2 dispatchPixel() {
  return ivec2(gl_GlobalInvocationID.xy) + camera.pixelOffset;
}

vec3 cameraRayDirection(vec2 pixelPosition) {
  vec2 ndc = pixelPosition / vec2(camera.imageSize) * 2.0 - 1.0;
  return normalize(camera.forward + ndc.x * camera.right - ndc.y * camera.up);
}
