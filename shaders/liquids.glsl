// Translucent liquids in the path (lighting/liquids.h): how each lighting mode draws a liquid
// surface over what lies behind it. Part of pathtrace.comp, after its Path and setRay.

// The faithful path's surface (path.face, NO_FACE for none; `atFace` false where the sky was
// shown instead) has been drawn, path.radiance. Where it is a translucent liquid or Quake 2's
// glass (render_scene.h engineBlend), the engine blends it over what lies behind it in the
// framebuffer's (the textures') gamma space: it goes into the veil and the camera ray goes on
// behind it, along the camera's line through the point it met (renderer/cpu radianceFaithful).
// False when the path has ended, its sample (the veil over the surface) in path.radiance.
bool faithfulBehindLiquid(inout Path path, bool atFace) {
  vec2 blend = vec2(1.0, 0.0);
  if (atFace && path.face != NO_FACE) {
    if ((faceFlags[path.face] & FACE_LIQUID) != 0u) blend = liquidBlend(path.face);
#ifdef BT_QUAKE2_GLASS
    else if (glassAlpha(path.face) > 0.0) blend = vec2(glassAlpha(path.face), 1.0 - glassAlpha(path.face));
#endif
  }
  if (blend.y > 0.0) {
    vec3 surface = linearToSrgb(path.radiance);
    path.veil += path.veilKeep * blend.x * surface;
#ifdef BT_FAITHFUL_FILTER
    path.veilKeep *= behindWeight(path.face, blend, surface);
#else
    path.veilKeep *= blend.y;
#endif
    vec3 toSurface = path.position - camera.origin;
    float t = length(toSurface);
    setRay(path, RAY_SURFACE, camera.origin, toSurface / t, INFINITY);
    path.tMin = t + SKIP_STEP;
    path.radiance = vec3(0.0);
    return true;
  }
  if (path.veil != vec3(0.0) || path.veilKeep != VeilKeep(1.0)) path.radiance = srgbToLinear(path.veil + path.veilKeep * linearToSrgb(path.radiance));
  return false;
}

// Where a physical ray passes a liquid, it goes on as past a hidden face.
bool passOn(inout Path path, float t) {
  path.tMin = t + SKIP_STEP;
  return true;
}

// A surface ray's hit on a translucent liquid (renderer/cpu radiancePhysical): drawn with
// probability self / (self + behind) of physical mode's opacity, else passed (true) and tinted;
// weighted by self + behind. An additive one (opacity 0) is always passed and adds its light.
bool physicalPassesLiquid(inout Path path, uint face, inout Rng rng) {
  GlMaterial m = materials[faces[face].material];
  vec2 blend = vec2(m.liquid.a, 1.0 - m.liquid.a); // physicalLiquidBlend
  if (!(blend.y > 0.0)) return false;
  float total = blend.x + blend.y;
  path.throughput *= total;
  if (rngNext(rng) * total < blend.x) return false;
  // liquid.rgb: the tint the light that crosses takes, or an additive surface's light (liquidAddedRadiance)
  if ((m.flags & MATERIAL_BLEND_ADD) != 0u) path.radiance += path.throughput * m.liquid.rgb;
  else path.throughput *= m.liquid.rgb;
  return true;
}
