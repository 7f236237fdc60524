// A pixel's path between the wavefront form's dispatches (pathtrace.comp's shade kernel): the
// Path fields that a later dispatch of this lighting mode reads, no more (path_fields.glsl's
// `kept`). Each is a load and a store per path and round, and code for the driver to compile:
// storing the whole Path (a faithful program's unused physical fields too) made the faithful
// kernel's first image later.
#include "gl_bindings.glsl"
#define STORED_PATH_FIELD(type, name, kept, onLoad) kept(type name;)
struct StoredPath {
  PATH_FIELDS(STORED_PATH_FIELD)
};

struct WavefrontPath {
  Rng rng;
  StoredPath path;
};
layout(std430, binding = BT_BINDING_WAVEFRONT_PATHS) buffer WavefrontPaths { WavefrontPath wavefrontPaths[]; };

#define STORE_PATH_FIELD(type, name, kept, onLoad) kept(s.name = p.name;)
void storePath(int slot, Rng rng, Path p) {
  wavefrontPaths[slot].rng = rng;
  StoredPath s;
  PATH_FIELDS(STORE_PATH_FIELD)
  wavefrontPaths[slot].path = s;
}

// The fields not kept are those this mode's later dispatches set before they read them, or
// start from their onLoad value.
#define LOAD_PATH_FIELD(type, name, kept, onLoad) onLoad(type, p.name) kept(p.name = s.name;)
Path loadPath(int slot, out Rng rng) {
  rng = wavefrontPaths[slot].rng;
  StoredPath s = wavefrontPaths[slot].path;
  Path p;
  PATH_FIELDS(LOAD_PATH_FIELD)
  return p;
}
