// The scene's storage buffers; binding numbers match renderer/gl/gl_structs.h (Binding).
#include "structs.glsl"

layout(std430, binding = 0) readonly buffer BvhNodes { GpuBvhNode nodes[]; };
layout(std430, binding = 1) readonly buffer Brushes { GpuBrush brushes[]; };
layout(std430, binding = 2) readonly buffer Faces { GpuFace faces[]; };
layout(std430, binding = 3) readonly buffer Materials { GpuMaterial materials[]; };
