// The tolerances of the rule on overlapping liquids (lighting/liquid_csg.h), one source for both
// tracers: lighting/liquid_csg.cpp includes this file as C++ and shaders/visible.glsl as GLSL.
// Hence only #defines of float literals without a suffix, which C++ reads as double (the CPU's
// rule works in the Scene's double planes) and GLSL as float (the GL tracer's, in its float
// planes: the two differ only where a point lies within float rounding of the tolerance).
#ifndef BT_LIQUID_CSG_CONSTANTS
#define BT_LIQUID_CSG_CONSTANTS

// A point this close to a plane lies on it (qbsp_faces.h kOnPlaneEpsilon, qbsp's ON_EPSILON-like
// tolerance for touching planes).
#define BT_LIQUID_CSG_ON_PLANE 0.01

// Two planes face the same way where 1 - cos of the angle between their normals is under this:
// qbsp merges planes closer than this. The GL tracer's table answers these tests on the CPU
// (renderer/gl/gl_lighting.h liquidCsgTable), so only C++ reads this one.
#define BT_LIQUID_CSG_NORMAL 1e-6

#endif
