// The flag bits and codes of the structs both tracers read, one source for both languages:
// scene/gpu_structs.h includes this file as C++ and shaders/structs.glsl as GLSL. Hence only
// #defines of integer literals, which both languages read alike.
#ifndef BT_SCENE_CONSTANTS
#define BT_SCENE_CONSTANTS

// GpuFace classes (RenderScene::faceFlags).
#define BT_FACE_HIDDEN 1u      // clip, trigger, skip, hint, origin, common/*: never seen
#define BT_FACE_SKY 2u         // sky*: the environment, and where sunlight comes from
#define BT_FACE_LIQUID 4u      // '*' textures / Quake 2 liquid contents: unlit unless _litwater
#define BT_FACE_NO_SHADOW 8u   // faithful mode: does not block light (brush entity without _shadow)
#define BT_FACE_EMISSIVE 16u   // has emissive texels or is a _surface template
#define BT_FACE_MASKED 32u     // alpha-tested: a hole where alpha < 0.5
#define BT_FACE_MASK_GT0 64u   // ... or where alpha is 0 (Quake 3 alphaFunc GT0)
#define BT_FACE_MASK_LT128 128u // ... or where alpha >= 0.5 (alphaFunc LT128)
// The GL tracer's face words add the face's lighting channels (RenderScene::faceChannels) above
// the classes, and one bit every face has; a ray's pass word (shaders/trace.glsl blocksRay) has
// the classes it passes in the low byte and, above, the channels a face must share to block it
// (physical mode: the every-face bit).
#define BT_FACE_CLASS_BITS 0xffu
#define BT_FACE_CHANNEL_SHIFT 8u
#define BT_FACE_CHANNEL_BITS 0x7fffff00u // channels 1 .. 2^22: a mask's higher bits are dropped
#define BT_FACE_ANY_CHANNEL 0x80000000u

// GpuLight::type.
#define BT_LIGHT_POINT 0u
#define BT_LIGHT_SUN 1u
#define BT_LIGHT_DOME 2u

// GpuLight::formula: ericw-tools' `delay`, then the kinds the compiler makes itself.
#define BT_FORMULA_LINEAR 0u
#define BT_FORMULA_INVERSE 1u
#define BT_FORMULA_INVERSE2 2u
#define BT_FORMULA_INFINITE 3u
#define BT_FORMULA_LOCAL_MIN 4u
#define BT_FORMULA_INVERSE2A 5u
#define BT_FORMULA_SURFACE_RADIOSITY 6u
#define BT_FORMULA_BOUNCE 7u
#define BT_FORMULA_Q3_POINT 8u
#define BT_FORMULA_Q3_LINEAR 9u
#define BT_FORMULA_Q3_AREA 10u

// GpuLight::flags.
#define BT_LIGHT_FLAG_START_OFF 1u
#define BT_LIGHT_FLAG_BLEED 2u
#define BT_LIGHT_FLAG_FROM_SURFACE 4u
#define BT_LIGHT_FLAG_FACE_MINLIGHT 8u
#define BT_LIGHT_FLAG_DIRT 16u
#define BT_LIGHT_FLAG_DIRT_RADIUS 32u
#define BT_LIGHT_FLAG_Q3_SPOT 64u
#define BT_LIGHT_FLAG_SUN_TABLE 128u

// GpuLuxelSample::flags.
#define BT_LUXEL_SAMPLE_OCCLUDED 1u
#define BT_LUXEL_SAMPLE_TWO_SIDED 2u
#define BT_LUXEL_SAMPLE_BOX_SHIFT 8u // the bits above: 1 + the sample's compiled face's box, 0 none
// shaders/bake.comp's firstPass of the dispatch that computes the lights' visapprox boxes
// (renderer/gl/gl_bake.cpp); -1 is the resolve, 0 and up the passes.
#define BT_BAKE_VIS_BOX_PASS -2

// renderer/gl/gl_structs.h GlMaterial::flags.
#define BT_GL_MATERIAL_HAS_BASE 1u
#define BT_GL_MATERIAL_HAS_NORMAL 2u
#define BT_GL_MATERIAL_HAS_EMISSIVE 4u // an emissive map with lit texels
#define BT_GL_MATERIAL_GGX 8u          // a PBR set: GGX + diffuse
#define BT_GL_MATERIAL_BLEND_ADD 16u   // a liquid drawn additively (GlMaterial::opacity)
#define BT_GL_MATERIAL_BLEND_FILTER 32u // a liquid that multiplies what lies behind by its colour

// renderer/gl/gl_structs.h GlBvhNode child references.
#define BT_GL_NO_CHILD 0u
#define BT_GL_LEAF_REF 0x80000000u

// A face index that names no face.
#define BT_NO_FACE 0xffffffffu

#endif
