// The fields of a Path (pathtrace.comp), each declared once here and expanded where they are
// needed: the struct itself (pathtrace.comp) and the wavefront form's copy of it between
// dispatches (wavefront_path.glsl), as pbrt-v4 generates its work items from one list.
//
// PATH_FIELDS(X) calls X(type, name, kept, onLoad) once per field:
//   kept:   the lighting modes that read the field in a later wavefront dispatch than the one
//           that set it, so the shade kernel stores it between dispatches: KEPT_ALWAYS,
//           KEPT_PHYSICAL, KEPT_FAITHFUL or KEPT_NEVER. Each stored field is a load and a store
//           per path and round, and code for the driver to compile: store no more than is read.
//   onLoad: what a path loaded in a mode that does not keep the field holds there: LOAD_UNSET
//           (the mode sets it before it reads it), LOAD_ZERO, or LOAD_NO_FACE.
// Adding a field is one line in one of the lists below. The lists are macros (one line each,
// continued with a backslash), so their comments are /* */ ones: a // comment would swallow the
// continuation.

// What lies behind the camera ray's translucent liquids weighs: one weight for every channel,
// except in a level whose Quake 3 blendFunc filter surfaces tint it (BT_FAITHFUL_FILTER). Two
// registers more, live for the whole path, cost a level without filters a fifth of its faithful
// samples/s in the megakernel (bench/README.md).
#ifdef BT_FAITHFUL_FILTER
#define VeilKeep vec3
#else
#define VeilKeep float
#endif

// The ray in flight.
#define PATH_FIELDS_RAY(X) \
  X(uint, kind, KEPT_ALWAYS, LOAD_UNSET) \
  X(vec3, origin, KEPT_ALWAYS, LOAD_UNSET) \
  X(vec3, dir, KEPT_ALWAYS, LOAD_UNSET) \
  X(float, tMin, KEPT_ALWAYS, LOAD_UNSET) \
  X(float, tMax, KEPT_ALWAYS, LOAD_UNSET) \
  /* A shadow ray's pass word (visible.glsl shadowPassFlags), set with the ray: the wavefront */ \
  /* form hands it to its trace kernel in the same dispatch, so it is not kept. */ \
  X(uint, passFlags, KEPT_NEVER, LOAD_ZERO) \
  /* Physical: the emitter point a shadow ray aims at (NO_FACE for other lights). Its emission */ \
  /* is read once the ray gets through, in advance(), at the one place that reads emission. */ \
  X(uint, emitterFace, KEPT_PHYSICAL, LOAD_NO_FACE) \
  X(vec3, emitterPoint, KEPT_PHYSICAL, LOAD_UNSET) \
  /* Hidden faces and inside hits passed along it (MAX_SKIPS, like the CPU's loops). */ \
  X(int, skips, KEPT_ALWAYS, LOAD_UNSET)

// The surface being lit: which light's ray is in flight (nextLightRay's position in the light
// grid's lists, the last = the emitters), and what that light adds if the ray gets through.
#define PATH_FIELDS_SURFACE(X) \
  X(int, depth, KEPT_PHYSICAL, LOAD_ZERO) /* surfaces before this one; 0 = the camera ray's */ \
  X(uint, face, KEPT_ALWAYS, LOAD_UNSET) \
  X(vec3, position, KEPT_ALWAYS, LOAD_UNSET) \
  X(vec3, normal, KEPT_ALWAYS, LOAD_UNSET) \
  X(vec3, wo, KEPT_PHYSICAL, LOAD_UNSET) /* physical: towards the previous vertex */ \
  X(uint, lightIndex, KEPT_ALWAYS, LOAD_UNSET) \
  X(vec3, pending, KEPT_ALWAYS, LOAD_UNSET) \
  /* Faithful: a delay 4 light, which raises a floor instead of adding. */ \
  X(bool, pendingIsFloor, KEPT_FAITHFUL, LOAD_UNSET)

// Faithful: the draw among the cell's bounce lights (faithfulBounceRay), where it stands.
#ifdef BT_FAITHFUL_BOUNCE_DRAW
#define PATH_FIELDS_BOUNCE_DRAW(X) \
  X(uint, bounceFirst, KEPT_FAITHFUL, LOAD_UNSET) /* list position of the first light drawn among; NO_BOUNCE_DRAW: none */ \
  X(uint, bounceLast, KEPT_FAITHFUL, LOAD_UNSET) /* ... of the last with a share (NO_BOUNCE_DRAW: none has one) */ \
  X(uint, bounceDrawn, KEPT_FAITHFUL, LOAD_UNSET) /* targets placed so far */ \
  X(float, bounceTotal, KEPT_FAITHFUL, LOAD_UNSET) /* the shares laid end to end */ \
  X(float, bounceCumulative, KEPT_FAITHFUL, LOAD_UNSET) /* ... up to the light the draw has reached */ \
  X(float, bounceTarget, KEPT_FAITHFUL, LOAD_UNSET) /* the next target */
#else
#define PATH_FIELDS_BOUNCE_DRAW(X)
#endif

// Faithful dirt: the surface's occlusion rays, traced before its lights.
#ifdef BT_FAITHFUL_DIRT
#define PATH_FIELDS_DIRT(X) \
  X(int, dirtRay, KEPT_FAITHFUL, LOAD_UNSET) /* rays set up so far */ \
  X(float, dirtSum, KEPT_FAITHFUL, LOAD_UNSET) /* their distances, each at most _dirtdepth */ \
  X(float, occlusion, KEPT_FAITHFUL, LOAD_UNSET) /* 0 open .. 1 enclosed, once all are back (lighting faithfulDirtOcclusion) */
#else
#define PATH_FIELDS_DIRT(X)
#endif

// Faithful mode: the lights at this surface, and over the path (lighting/ faithfulLight (LightSet::All),
// faithfulPathEnd, radianceFaithful). Physical mode (renderer/cpu radiancePhysical). The sample.
#define PATH_FIELDS_LIGHT(X) \
  X(vec3, lightSum, KEPT_FAITHFUL, LOAD_UNSET) \
  X(vec3, lightFloor, KEPT_FAITHFUL, LOAD_UNSET) \
  X(vec3, lit, KEPT_NEVER, LOAD_ZERO) /* the light sum with its floors */ \
  X(vec3, texture, KEPT_FAITHFUL, LOAD_UNSET) /* the first surface's texture colour (sRGB-encoded) ... */ \
  X(vec3, fullbright, KEPT_FAITHFUL, LOAD_UNSET) /* ... and its emissive texels */ \
  /* Faithful: the translucent liquids the camera ray went through, blended (gamma space), and */ \
  /* what lies behind them weighs (faithfulBehindLiquid; VeilKeep). */ \
  X(vec3, veil, KEPT_FAITHFUL, LOAD_UNSET) \
  X(VeilKeep, veilKeep, KEPT_FAITHFUL, LOAD_UNSET) \
  X(Bsdf, bsdf, KEPT_PHYSICAL, LOAD_UNSET) \
  X(vec3, throughput, KEPT_PHYSICAL, LOAD_UNSET) \
  X(float, prevBsdfPdf, KEPT_PHYSICAL, LOAD_UNSET) /* 0: camera ray (no MIS weight on what it sees) */ \
  X(vec3, radiance, KEPT_PHYSICAL, LOAD_ZERO) /* the sample, once the path has ended (0 until then in faithful mode) */

// Faithful negative lights (lighting faithful::subtractedLight): their sum, taken off after the
// floors, and whether the pending share is one of them. NEGATIVE_ONLY(code): code only in the
// programs of levels that have such lights.
#ifdef BT_FAITHFUL_NEGATIVE
#define PATH_FIELDS_NEGATIVE(X) \
  X(vec3, lightNegative, KEPT_FAITHFUL, LOAD_UNSET) \
  X(bool, pendingIsNegative, KEPT_FAITHFUL, LOAD_UNSET)
#define NEGATIVE_ONLY(code) code
#else
#define PATH_FIELDS_NEGATIVE(X)
#define NEGATIVE_ONLY(code)
#endif

#define PATH_FIELDS(X) \
  PATH_FIELDS_RAY(X) PATH_FIELDS_SURFACE(X) PATH_FIELDS_BOUNCE_DRAW(X) PATH_FIELDS_DIRT(X) PATH_FIELDS_NEGATIVE(X) PATH_FIELDS_LIGHT(X)

// kept(x): x where this program's lighting mode keeps the field, else nothing.
#define KEPT_ALWAYS(x) x
#define KEPT_NEVER(x)
#ifdef BT_LIGHTING_PHYSICAL
#define KEPT_PHYSICAL(x) x
#define KEPT_FAITHFUL(x)
#else
#define KEPT_PHYSICAL(x)
#define KEPT_FAITHFUL(x) x
#endif

// onLoad(type, field): the value a loaded path's field starts from, before a kept one is read.
#define LOAD_UNSET(type, field)
#define LOAD_ZERO(type, field) field = type(0);
#define LOAD_NO_FACE(type, field) field = NO_FACE;
