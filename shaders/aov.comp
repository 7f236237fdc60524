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
  // The first surface gives the normal, depth and face; a translucent liquid's albedo is
  // blended over what lies behind it as the engine blends colours (renderer/cpu albedoAlong),
  // the ray going on along the camera's line: one call of the traversal for all of it.
  SurfaceHit hit;
  vec3 veil = vec3(0.0), albedo;
  vec3 keep = vec3(1.0);
  float tMin = 0.0;
  vec3 rayDir = dir;
  for (bool first = true;; first = false) {
    SurfaceHit s = traceVisibleFrom(camera.origin, rayDir, tMin);
    if (first) hit = s;
    if (!hit.found) {
      imageStore(albedoImage, pixel, vec4(0.0));
      imageStore(normalImage, pixel, vec4(0.0, 0.0, 0.0, uintBitsToFloat(0x7f800000u))); // +inf: GLSL leaves 1/0 undefined
      imageStore(faceImage, pixel, uvec4(0u));
      return;
    }
    albedo = vec3(0.0);
    if (s.found) {
      GpuFace f = faces[s.face];
      GlMaterial m = materials[f.material];
      // A sky face of a level with sky images shows them along the ray (sky.glsl).
      bool sky = (faceFlags[s.face] & FACE_SKY) != 0u && world.skySize != 0u;
      albedo = sky ? skyRadiance(dir) : srgbToLinear(materialBaseColor(m, faceUv(f, m, s.position)).rgb);
    }
    vec2 blend = s.found && (faceFlags[s.face] & FACE_LIQUID) != 0u ? liquidBlend(s.face) : vec2(1.0, 0.0);
    if (!(blend.y > 0.0)) break;
    veil += keep * blend.x * linearToSrgb(albedo);
    keep *= behindWeight(s.face, blend, linearToSrgb(albedo));
    vec3 toSurface = s.position - camera.origin;
    tMin = length(toSurface) + SKIP_STEP;
    rayDir = toSurface / length(toSurface);
  }
  if (veil != vec3(0.0) || keep != vec3(1.0)) albedo = srgbToLinear(veil + keep * linearToSrgb(albedo));
  imageStore(albedoImage, pixel, vec4(albedo, 1.0));
  imageStore(normalImage, pixel, vec4(hit.normal, hit.t)); // facing the ray where a liquid is seen from inside (BT_LIQUID_CSG)
  imageStore(faceImage, pixel, uvec4(hit.face + 1u));
}
