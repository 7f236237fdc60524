#version 450
#extension GL_GOOGLE_include_directive : require
#include "gl_bindings.glsl"
#ifdef BT_TEXTURES_BINDLESS
#extension GL_ARB_bindless_texture : require
#endif
// Primary-ray AOVs: albedo, world normal, depth and face index per pixel, one ray through each
// pixel centre (deterministic, so the CPU reference gives the same image).
#include "scene_buffers.glsl"
#include "textures.glsl"
#include "sky.glsl"
#include "trace.glsl"
#include "visible.glsl"
#include "camera.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = BT_IMAGE_ALBEDO) uniform writeonly image2D albedoImage; // rgb linear albedo, a = coverage
layout(rgba32f, binding = BT_IMAGE_NORMAL_DEPTH) uniform writeonly image2D normalImage; // xyz world normal, w = distance along the ray
layout(r32ui, binding = BT_IMAGE_FACE) uniform writeonly uimage2D faceImage;   // Scene::faces index + 1, 0 = miss

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, camera.imageSize))) return;
  vec3 dir = cameraRayDirection(vec2(pixel) + 0.5);
  SurfaceHit hit = traceVisible(camera.origin, dir);
  if (!hit.found) {
    imageStore(albedoImage, pixel, vec4(0.0));
    imageStore(normalImage, pixel, vec4(0.0, 0.0, 0.0, uintBitsToFloat(0x7f800000u))); // +inf: GLSL leaves 1/0 undefined
    imageStore(faceImage, pixel, uvec4(0u));
    return;
  }
  GpuFace f = faces[hit.face];
  GlMaterial m = materials[f.material];
  // A sky face of a level with sky images shows them along the ray (sky.glsl).
  bool sky = (faceFlags[hit.face] & FACE_SKY) != 0u && world.skySize != 0u;
  vec3 albedo = sky ? skyRadiance(dir) : srgbToLinear(materialBaseColor(m, faceUv(f, m, hit.position)).rgb);
  imageStore(albedoImage, pixel, vec4(albedo, 1.0));
  imageStore(normalImage, pixel, vec4(f.plane.xyz, hit.t));
  imageStore(faceImage, pixel, uvec4(hit.face + 1u));
}
