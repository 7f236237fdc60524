// The scene's storage buffers; binding numbers match renderer/gl/gl_structs.h (Binding).
#include "gl_bindings.glsl"
#include "structs.glsl"

// TraceScene's faces (bvh/trace_scene.h), unchanged.
layout(std430, binding = BT_BINDING_FACES) readonly buffer Faces { GpuFace faces[]; };
#ifdef BT_TRACE_SOFTWARE
// With BT_TRACE_SOFTWARE (llvmpipe; trace.glsl) the traversal reads the BVH nodes (GlBvhNode, made from TraceScene's tree at
// upload), TraceScene's brushes and slanted-side lists, and the face planes through buffer
// textures, one 16-byte texel (a row of the struct) per fetch; units as renderer/gl/gl_structs.h
// TexelUnit. On llvmpipe a storage-buffer load at addresses that differ between invocations
// runs one branchy scalar load per invocation and component, while a texel fetch is one vector
// gather, which the traversal runs faster. GPUs (NVIDIA) read both through the same caches.
layout(binding = BT_TEXEL_NODES) uniform usamplerBuffer nodeTexels;  // GlBvhNode (gl_structs.h): 4 texels (RGBA32UI)
layout(binding = BT_TEXEL_BRUSHES) uniform usamplerBuffer brushTexels; // GpuBrush: 4 texels (RGBA32UI)
layout(binding = BT_TEXEL_SIDES) uniform usamplerBuffer sideTexels;  // TraceScene::sides(): 1 texel each (R32UI)
layout(binding = BT_TEXEL_FACES) uniform samplerBuffer faceTexels;   // GpuFace: 4 texels (RGBA32F), the plane first
#endif
layout(std430, binding = BT_BINDING_MATERIALS) readonly buffer Materials { GlMaterial materials[]; };
layout(std430, binding = BT_BINDING_LIGHTS) readonly buffer Lights { GpuLight lights[]; };
layout(std430, binding = BT_BINDING_SURFACE_LIGHTS) readonly buffer SurfaceLights { GpuLight surfaceLights[]; }; // per material
layout(std430, binding = BT_BINDING_EMITTERS) readonly buffer Emitters { GpuEmitter emitters[]; };
layout(std430, binding = BT_BINDING_FACE_FLAGS) readonly buffer FaceFlags { uint faceFlags[]; }; // per face: FACE_* (RenderScene::faceFlags)

// Worldspawn lighting (lighting WorldLighting) and the integrator settings.
layout(std140, binding = BT_UNIFORM_WORLD) uniform World {
  vec3 minlight;      // light units
  float range;        // _range
  float scaledist;    // _dist
  float bouncescale;  // _bouncescale
  int faithfulBounces;// _bounce
  uint litwater;      // _litwater
  uint lightCount;
  uint emitterCount;
  float emitterArea;
  uint physical;      // 0 faithful, 1 physical (pathtrace.comp: BT_LIGHTING_PHYSICAL decides)
  int bounces;        // physical: --bounces
  // Faithful dirt (lighting DirtSettings), read with BT_FAITHFUL_DIRT only.
  uint dirtMode;      // 0: the fixed 48-ray pattern, 1: random rays in the cone
  float dirtDepth;    // _dirtdepth
  float dirtAngle;    // _dirtangle, radians
  float dirtScale;    // worldspawn _dirtscale / _dirtgain (minlight's dirt)
  float dirtGain;
  uint minlightDirt;  // _minlight_dirt
  float overbrightOne;// lighting WorldLighting::overbrightOne: the game's display (Quake 128, Quake 2 and Half-Life 255)
  vec3 ambient;       // lighting WorldLighting::ambient: q3map2's `_ambient`, added to the light sum
  uint skySize;       // the sky texture's face edge in texels (sky.glsl), 0 without sky images
  uint luxelDisplay;  // lighting WorldLighting::luxelDisplay (BT_LUXEL_DISPLAY_*, lightmaps.glsl shownLuxel)
  float clampIndirect;// physical: --clamp-indirect, units (renderer IntegratorSettings::clampIndirect)
} world;
