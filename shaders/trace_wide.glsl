// traceRay over the compressed 8-wide BVH (TraceLayout::Wide, BT_TRACE_WIDE), the walk of Ylitie,
// Karras and Laine, "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs"
// (HPG 2017); included by trace.glsl in place of the binary walk, with the hardware layout's
// storage-buffer reads. Same contract, same hits bit for bit: the brush and triangle tests are
// trace.glsl's, the closest hit is chosen by closer(), a total order, so it does not depend on
// the order the leaves are met in, and every child box holds its subtree's exact box (quantised
// outwards, renderer/gl/gl_wide_bvh.cpp), so a child whose brushes the binary walk would test for
// a hit at t <= best t is entered here too (boxOverlaps is monotonic in the box).
//
// Node layout (renderer/gl/gl_structs.h GlWideNode), BT_GL_WIDE_NODE_ROWS rows of 16 bytes:
//   row 0: origin.xyz (floats), w = exponent.x | exponent.y << 8 | exponent.z << 16 | imask << 24
//   row 1: x = childBase (node row of the first interior child), y = leafBase (first primitive),
//          zw = meta[0..7] (a byte per child slot: 0 empty, BT_GL_WIDE_INNER interior,
//          count << 5 | offset a leaf of primitives leafBase + offset .. + count)
//   row 2: qlo.x[0..7], qlo.y[0..7]; row 3: qlo.z[0..7], qhi.x[0..7]; row 4: qhi.y[0..7], qhi.z[0..7]
// Child slot i's box: origin + q[i] * scale, scale per axis the float with exponent bits
// `exponent` (2^(exponent - 127)). The node buffer's row 0 is GlWideHeader: x the brushes' root
// row, y the triangles' (NO_CHILD: none), z the brush-buffer row of the first triangle.
//
// Children sit in slots by octant (the ray's octant: bit a set for a negative direction along
// axis a): the walk visits slot (k ^ octant) k-th, nearest first, with no sort. The stack holds
// node groups, uvec2(childBase, hits << 24 | imask): a node's interior children still to visit
// (bit k for slot k ^ octant) and its imask, from which a child's row is computed. One entry per
// level of the wide tree at most: BT_GL_WIDE_MAX_DEPTH (the collapse checks the depth).

const uint WIDE_NODE_ROWS = BT_GL_WIDE_NODE_ROWS;
const uint WIDE_INNER = BT_GL_WIDE_INNER;
const uint WIDE_FIRST_CHILD = 1u << 24; // a group's hit bit for the first child in visiting order

uvec2 wideStack[BT_GL_WIDE_MAX_DEPTH];

// Byte `slot` of the 8 in two words.
uint slotByte(uint lo, uint hi, uint slot) {
  return bitfieldExtract(slot < 4u ? lo : hi, int(8u * (slot & 3u)), 8);
}

// The node at `row`: sets `children` to the group of its interior children whose boxes the ray
// enters within tLimit, and returns the leaf mask (bit k: primitive leafBase + k) of its leaf
// children's primitives likewise; `leafBase` their first.
uint visitWideNode(TraceRay r, uint octant, uint row, float tLimit, out uvec2 children, out uint leafBase) {
  uvec4 r0 = nodeRows[row], r1 = nodeRows[row + 1u], r2 = nodeRows[row + 2u], r3 = nodeRows[row + 3u], r4 = nodeRows[row + 4u];
  vec3 origin = uintBitsToFloat(r0.xyz);
  vec3 scale = uintBitsToFloat(uvec3(r0.w & 0xffu, (r0.w >> 8) & 0xffu, (r0.w >> 16) & 0xffu) << 23);
  uint hits = 0u, leaves = 0u;
  for (uint slot = 0u; slot < 8u; ++slot) {
    uint meta = slotByte(r1.z, r1.w, slot);
    if (meta == 0u) continue;
    vec3 qlo = vec3(slotByte(r2.x, r2.y, slot), slotByte(r2.z, r2.w, slot), slotByte(r3.x, r3.y, slot));
    vec3 qhi = vec3(slotByte(r3.z, r3.w, slot), slotByte(r4.x, r4.y, slot), slotByte(r4.z, r4.w, slot));
    float entry;
    if (!boxOverlaps(r, origin + qlo * scale, origin + qhi * scale, tLimit, entry)) continue;
    if (meta == WIDE_INNER) hits |= WIDE_FIRST_CHILD << (slot ^ octant);
    else leaves |= ((1u << (meta >> 5)) - 1u) << (meta & 31u);
  }
  children = uvec2(r1.x, hits | (r0.w >> 24));
  leafBase = r1.y;
  return leaves;
}

Hit traceRay(TraceRay r, bool anyHit, uint passFlags) {
  Hit best = Hit(r.tMax, NO_FACE, false);
  uvec4 header = nodeRows[0];
  uint octant = (r.dir.x < 0.0 ? 1u : 0u) | (r.dir.y < 0.0 ? 2u : 0u) | (r.dir.z < 0.0 ? 4u : 0u);
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
    if (group.y > 0x00ffffffu) wideStack[size++] = group;
    uint leafBase;
    uint leaves = visitWideNode(r, octant, row, best.t, group, leafBase);
    while (leaves != 0u) {
      uint i = leafBase + uint(findLSB(leaves));
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
    if (group.y > 0x00ffffffu) continue;
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
