// Where the GL tracer binds what its shaders read, one source for both languages:
// renderer/gl/gl_structs.h and gl_textures.h include this file as C++, the shaders as GLSL.
// Hence only #defines of integer literals, which both languages read alike.
#ifndef BT_GL_BINDINGS
#define BT_GL_BINDINGS

// Storage buffers (gl_structs.h Binding).
#define BT_BINDING_NODES 0
#define BT_BINDING_BRUSHES 1
#define BT_BINDING_FACES 2
#define BT_BINDING_MATERIALS 3
#define BT_BINDING_LIGHTS 4
#define BT_BINDING_SURFACE_LIGHTS 5
#define BT_BINDING_EMITTERS 6
#define BT_BINDING_SIDES 7
#define BT_BINDING_FACE_FLAGS 8
#define BT_BINDING_LIGHT_GRID 9     // GpuLightGrid, then its GpuLightCell array
#define BT_BINDING_LIGHT_INDICES 10 // the grid's uint index array into the light buffer
// The wavefront path tracer's per-pixel state.
#define BT_BINDING_WAVEFRONT_RAYS 11
#define BT_BINDING_WAVEFRONT_HITS 12
#define BT_BINDING_WAVEFRONT_PATHS 13
#define BT_BINDING_WAVEFRONT_ENDED_COUNT 14
#define BT_BINDING_LIGHTMAPS 15
// The faithful bake runs without the wavefront's buffers and takes their points: drivers need
// offer only 16 storage blocks to a compute shader.
#define BT_BINDING_BAKE_SAMPLES 11
#define BT_BINDING_BAKE_SUMS 12
#define BT_BINDING_BAKE_SKY_DOME 13

// Texture units: the material texture arrays take units 0 .. BT_MAX_TEXTURE_ARRAYS - 1, the
// traversal's buffer textures (gl_structs.h TexelUnit) the units after them.
#define BT_TEXTURE_ARRAYS_UNIT 0
#define BT_MAX_TEXTURE_ARRAYS 16
#define BT_TEXEL_NODES 16
#define BT_TEXEL_BRUSHES 17
#define BT_TEXEL_SIDES 18
#define BT_TEXEL_FACES 19
#define BT_TEXEL_UNIT_END 20
#define BT_TEXTURE_SKY 20        // the level's sky by direction (sky.glsl): RGBA16F, six layers
#define BT_TEXTURE_UNIT_COUNT 21 // the units a context must offer the tracer's compute shaders

// Uniform blocks.
#define BT_UNIFORM_CAMERA 0
#define BT_UNIFORM_WORLD 1

// Image units, per program.
#define BT_IMAGE_ACCUMULATION 0  // pathtrace.comp's sum of samples, tonemap.comp's input
#define BT_IMAGE_DISPLAY 1       // tonemap.comp's output
#define BT_IMAGE_ALBEDO 0        // aov.comp
#define BT_IMAGE_NORMAL_DEPTH 1  // aov.comp
#define BT_IMAGE_FACE 2          // aov.comp
#define BT_IMAGE_PRIMARY_HITS 0  // raybench.comp
#define BT_IMAGE_BOUNCE_T 1      // raybench.comp
#define BT_IMAGE_DENOISE_IN 0            // denoise.comp: the pass's input (the beauty, or the last pass's irradiance)
#define BT_IMAGE_DENOISE_OUT 1           // denoise.comp: its output
#define BT_IMAGE_DENOISE_ALBEDO 2        // denoise.comp
#define BT_IMAGE_DENOISE_NORMAL_DEPTH 3  // denoise.comp
#define BT_IMAGE_DENOISE_RAW 4           // denoise.comp: the beauty, read again by the last pass

#endif
