// traceRay over the compressed 8-wide BVH (TraceLayout::Wide, BT_TRACE_WIDE), the walk of Ylitie,
// Karras and Laine, "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs"
// (HPG 2017); included by trace.glsl in place of the binary walk, with the hardware layout's
// storage-buffer reads. Same contract, same hits bit for bit: the brush and triangle tests are
// trace.glsl's, the closest hit is chosen by closer(), a total order, so it does not depend on
// the order the leaves are met in, and the node test (intersectWideNode) never culls a child
// holding a brush whose hit the binary walk returns (it may enter more; the proof is there).
//
// Node layout (renderer/gl/gl_structs.h GlWideNode), BT_GL_WIDE_NODE_ROWS rows of 16 bytes:
//   row 0: origin.xyz (floats), w = exponent.x | exponent.y << 8 | exponent.z << 16 | imask << 24
//   row 1: x = childBase (node row of the first interior child), y = leafBase (first primitive),
//          zw = meta[0..7] (a byte per child slot: 0 empty, 1 << 5 | (24 + slot) interior,
//          count in unary << 5 | offset a leaf of primitives leafBase + offset .. + count)
//   row 2: qlo.x[0..7], qlo.y[0..7]; row 3: qlo.z[0..7], qhi.x[0..7]; row 4: qhi.y[0..7], qhi.z[0..7]
// Child slot i's box: origin + q[i] * scale, scale per axis the float with exponent bits
// `exponent` (2^(exponent - 127)). The node buffer's row 0 is GlWideHeader: x the brushes' root
// row, y the triangles' (NO_CHILD: none), z the brush-buffer row of the first triangle.
//
// Children sit in slots by octant (the ray's octant: bit a set for a negative direction along
// axis a): the walk visits slot (k ^ octant) k-th, nearest first, with no sort. A node's test
// returns its hit mask, built from the metas with no branch (the paper's): bit 24 + k for the
// interior child visited k-th, bits 0-23 for the leaf children's primitives. The stack holds
// node groups, uvec2(childBase, hits & 0xff000000 | imask): a node's interior children still to
// visit and its imask, from which a child's row is computed. One entry per level of the wide
// tree at most: BT_GL_WIDE_MAX_DEPTH (the collapse checks it).

const uint WIDE_NODE_ROWS = BT_GL_WIDE_NODE_ROWS;
const uint WIDE_FIRST_CHILD = 1u << BT_GL_WIDE_INNER_BIT; // a group's hit bit for the first child in visiting order
const uint WIDE_LEAF_BITS = WIDE_FIRST_CHILD - 1u;

uvec2 wideStack[BT_GL_WIDE_MAX_DEPTH];

// The 4 bytes of a word as floats, exactly: the byte in the mantissa of 2^23, less 2^23 (a logic
// operation and an add each, where a conversion instruction runs at a quarter of the rate).
vec4 wideBytes(uint word) {
  return uintBitsToFloat(((uvec4(word) >> uvec4(0u, 8u, 16u, 24u)) & 0xffu) | 0x4b000000u) - 8388608.0;
}

// The node test, the paper's: the ray is taken into the node's quantised frame once per node
// (per axis a slope sI and offsets bN, bF), then each slot's near and far t per axis are one
// multiply-add on its 8-bit bounds, the slots' hit bits built with no branch. Returns the hit
// mask (see above) of the children whose boxes the ray may meet within (tMin, tLimit].
//
// Why it never culls what the binary walk finds. A brush's hit t (trace.glsl hitBrush) lies
// within its box's interval as intersectBox computes it, per axis T = fl(fl(p - o) * invD), and a
// hit that can be the closest one has tMin < t <= tLimit (every tLimit the walk passes is at
// least the final hit's t). The child's box holds the brush's box (quantised outwards with the
// float sum, gl_wide_bvh.cpp quantise), so in exact arithmetic its slab ends are at least as
// wide; what remains is rounding: of the float sum at build (u |origin + q s|), of the brush's T
// (2u |p - o| |invD|), and here of b, bN, q * sI and the add (sI = s * invD is exact, s a power
// of two). Each is at most a few u * M, M = (|origin - o| + |origin| + 256 s) |invD|, since
// every p of the node lies within origin + [0, 255] s; the offsets are widened by
// WIDE_SLACK * M = 32u * M, above the sum (about 9u * M), so each axis's near is at most the
// brush's and its far at least, and the max/min and the comparison (the binary walk's own,
// boxOverlaps) keep the order. Culling less than that costs at most 2^-19 of a node's span.
// A zero direction component (invD 0: no bound, or a miss when the origin is outside the slab,
// trace.glsl clipSlab) is a slab test in q units instead: x the origin's position, rounded
// within 2^-16 of a unit while it is within the node's 256 units (further off it only needs its
// side, which rounding keeps, and is clamped), near = (q_lo - x - 1) * WIDE_BIG and far =
// (q_hi - x + 1) * WIDE_BIG: below -WIDE_BIG / 2 and above WIDE_BIG / 2 when the origin is in
// the child's slab (no bound for any t a ray can reach: a hit beyond 2^116 would need
// direction components below the 2^-100 that makeTraceRay flushes, on coordinates below 2^16),
// and a miss only when the origin is a unit or more outside.
const float WIDE_SLACK = 1.0 / 524288.0;      // 2^-19
const float WIDE_BIG = 1.6615349947311448e35; // 2^117: (255 + 260) * 2^117 is below FLT_MAX

// The ray in a node's frame (intersectWideNode): per axis the slope and the near and far offsets.
struct WideFrame {
  vec3 slope, nearOffset, farOffset;
};

// Four slots' hit bits: their metas, and per axis the words of their near and far bounds.
uint wideQuad(WideFrame f, uint octant4, uint meta, uvec3 nearWords, uvec3 farWords, float tMin, float tLimit) {
  vec4 tNear = max(max(wideBytes(nearWords.x) * f.slope.x + f.nearOffset.x, wideBytes(nearWords.y) * f.slope.y + f.nearOffset.y),
                   max(wideBytes(nearWords.z) * f.slope.z + f.nearOffset.z, vec4(tMin)));
  vec4 tFar = min(min(wideBytes(farWords.x) * f.slope.x + f.farOffset.x, wideBytes(farWords.y) * f.slope.y + f.farOffset.y),
                  min(wideBytes(farWords.z) * f.slope.z + f.farOffset.z, vec4(tLimit)));
  // Per byte: interior when its index is 24 or more (bits 3 and 4), whose index is then XORed
  // with the octant (visiting order); the unary count (1 for interior) shifted to the index.
  uint inner = (meta & (meta << 1)) & 0x10101010u;
  uint index = (meta ^ (octant4 & ((inner >> 4) * 0xffu))) & 0x1f1f1f1fu;
  uint count = (meta >> 5) & 0x07070707u;
  const uvec4 byteShift = uvec4(0u, 8u, 16u, 24u);
  uvec4 bits = ((uvec4(count) >> byteShift) & 0xffu) << ((uvec4(index) >> byteShift) & 0xffu);
  bits = mix(uvec4(0u), bits, lessThanEqual(tNear, tFar));
  return (bits.x | bits.y) | (bits.z | bits.w);
}

uint intersectWideNode(TraceRay r, uint octant4, uvec4 r0, uvec4 r1, uvec4 r2, uvec4 r3, uvec4 r4, float tLimit) {
  vec3 origin = uintBitsToFloat(r0.xyz);
  uvec3 exponent = uvec3(r0.w, r0.w >> 8, r0.w >> 16) & 0xffu;
  vec3 scale = uintBitsToFloat(exponent << 23), inverseScale = uintBitsToFloat((254u - exponent) << 23);
  bvec3 zero = equal(r.invDir, vec3(0.0));
  vec3 rel = origin - r.origin;
  vec3 b = rel * r.invDir;
  vec3 slack = WIDE_SLACK * (abs(rel) + abs(origin) + 256.0 * scale) * abs(r.invDir);
  vec3 x = clamp(-rel * inverseScale, -4.0, 259.0);
  WideFrame f = WideFrame(mix(scale * r.invDir, vec3(WIDE_BIG), zero), mix(b - slack, -(x + 1.0) * WIDE_BIG, zero),
                          mix(b + slack, (1.0 - x) * WIDE_BIG, zero));
  // The near bound per axis is the low one for a ray going up that axis (or not moving), the
  // high one going down; the words of slots 0-3 (x of each pair) then 4-7 (y).
  bvec3 down = lessThan(r.dir, vec3(0.0));
  uvec2 nearX = down.x ? r3.zw : r2.xy, farX = down.x ? r2.xy : r3.zw;
  uvec2 nearY = down.y ? r4.xy : r2.zw, farY = down.y ? r2.zw : r4.xy;
  uvec2 nearZ = down.z ? r4.zw : r3.xy, farZ = down.z ? r3.xy : r4.zw;
  // A node of up to 4 children holds them in slots 0-3 (gl_wide_bvh.cpp slotsByOctant): a third
  // of lq_e4m3's nodes have 2, the most common count.
  uint hits = wideQuad(f, octant4, r1.z, uvec3(nearX.x, nearY.x, nearZ.x), uvec3(farX.x, farY.x, farZ.x), r.tMin, tLimit);
  if (r1.w != 0u) hits |= wideQuad(f, octant4, r1.w, uvec3(nearX.y, nearY.y, nearZ.y), uvec3(farX.y, farY.y, farZ.y), r.tMin, tLimit);
  return hits;
}

Hit traceRay(TraceRay r, bool anyHit, uint passFlags) {
  Hit best = Hit(r.tMax, NO_FACE, false);
  uvec4 header = nodeRows[0];
  uint octant = (r.dir.x < 0.0 ? 1u : 0u) | (r.dir.y < 0.0 ? 2u : 0u) | (r.dir.z < 0.0 ? 4u : 0u);
  uint octant4 = octant * 0x01010101u;
  // A group of one child, the root: imask 0 puts it at childBase whatever its slot.
  uvec2 group = uvec2(header.x, WIDE_FIRST_CHILD);
  int size = 0;
  bool inTriangles = false;
  while (true) {
    // The group's next child in visiting order; the rest of the group waits on the stack.
    uint k = uint(findLSB(group.y >> 24));
    uint slot = k ^ octant;
    uint row = group.x + WIDE_NODE_ROWS * uint(bitCount(group.y & ((1u << slot) - 1u) & 0xffu));
    group.y &= ~(WIDE_FIRST_CHILD << k);
    if (group.y > WIDE_LEAF_BITS) wideStack[size++] = group;
    uvec4 r0 = nodeRows[row], r1 = nodeRows[row + 1u];
    uint hits = intersectWideNode(r, octant4, r0, r1, nodeRows[row + 2u], nodeRows[row + 3u], nodeRows[row + 4u], best.t);
    group = uvec2(r1.x, (hits & ~WIDE_LEAF_BITS) | (r0.w >> 24));
    uint leaves = hits & WIDE_LEAF_BITS;
    while (leaves != 0u) {
      uint i = r1.y + uint(findLSB(leaves));
      leaves &= leaves - 1u;
      Hit hit;
      if (!(inTriangles ? hitTriangle(r, header.z, i, best.t, hit) : hitBrush(r, i, best.t, hit))) continue;
      if (anyHit) {
        if ((!hit.inside || blocksFromInside(inTriangles, i, passFlags)) && blocksRay(faceFlags[hit.face], passFlags) &&
            !maskedOut(hit.face, r.origin + r.dir * hit.t))
          return hit;
      } else if (closer(hit, best)) {
        best = hit;
      }
    }
    if (group.y > WIDE_LEAF_BITS) continue;
    if (size > 0) {
      group = wideStack[--size];
      continue;
    }
    if (inTriangles || header.y == NO_CHILD) break;
    inTriangles = true;
    group = uvec2(header.y, WIDE_FIRST_CHILD);
  }
  return best;
}
