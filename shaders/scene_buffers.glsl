// The scene's storage buffers; binding numbers match renderer/gl/gl_structs.h (Binding).
#include "structs.glsl"

// TraceScene's arrays (bvh/trace_scene.h), unchanged.
layout(std430, binding = 0) readonly buffer BvhNodes { GpuBvhNode nodes[]; };
layout(std430, binding = 1) readonly buffer Brushes { GpuBrush brushes[]; };
layout(std430, binding = 2) readonly buffer Faces { GpuFace faces[]; };
layout(std430, binding = 7) readonly buffer Sides { uint sides[]; }; // slanted face indices per brush
layout(std430, binding = 3) readonly buffer Materials { GpuMaterial materials[]; };
layout(std430, binding = 4) readonly buffer Lights { GpuLight lights[]; };
layout(std430, binding = 5) readonly buffer SurfaceLights { GpuLight surfaceLights[]; }; // per material
layout(std430, binding = 6) readonly buffer Emitters { GpuEmitter emitters[]; };
layout(std430, binding = 8) readonly buffer FaceFlags { uint faceFlags[]; }; // per face: FACE_* (RenderScene::faceFlags)

// Worldspawn lighting (renderer/cpu WorldLighting) and the integrator settings.
layout(std140, binding = 1) uniform World {
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
  // Faithful dirt (renderer/cpu DirtSettings), read with BT_FAITHFUL_DIRT only.
  uint dirtMode;      // 0: the fixed 48-ray pattern, 1: random rays in the cone
  float dirtDepth;    // _dirtdepth
  float dirtAngle;    // _dirtangle, radians
  float dirtScale;    // worldspawn _dirtscale / _dirtgain (minlight's dirt)
  float dirtGain;
  uint minlightDirt;  // _minlight_dirt
} world;
