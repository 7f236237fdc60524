"""Writes the liquid maps (tests/render/liquids_test.cpp, tests/gl/gl_liquids_test.cpp): a room
whose floor has a pool with a coloured floor, seen from above by an info_intermission.

- pool.map: the pool holds `*water_blue` under worldspawn `_wateralpha 0.5`;
  pool_opaque.map: the same water without the key (the engine's default: opaque);
  pool_dry.map: the pool without water. The engine draws pool.map's water as
  0.5 x water + 0.5 x pool_dry.map's floor, in its framebuffer's gamma space.
- pools.map: three pools side by side, water, slime and lava (`*water_blue`, `*slime_green`,
  `*lava_glow`), under four lights, and a wall beside the lava for physical mode;
  lava_dark.map: the lava pool and its wall without any light.
- csg_water.map: pool.map's water made of three `*water_blue` brushes that overlap (two halves
  sharing a middle, a third inside them): qbsp merges them into pool.map's one volume;
  csg_lava.map: a `*lava_glow` pool (`_lavaalpha 0.5`) with a `*water_blue` box inside it: qbsp
  keeps the water's faces, from both sides (lighting/liquid_csg.h).
Run it again after editing; the output is deterministic. Needs only the standard library.
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
from generate_start import box, entity, write_png  # noqa: E402

# Flat colours (sRGB bytes), so that the engine's blend is a number the tests can compute.
COLOURS = {
    "star_water_blue": (40, 90, 200),
    "star_slime_green": (70, 150, 40),
    "star_lava_glow": (230, 90, 20),
    "poolfloor": (220, 200, 60),
    "poolwall": (120, 120, 120),
}

X0, X1, Y0, Y1, Z1 = -256, 256, -192, 192, 192  # the room
T = 16
DEPTH = 64     # of each pool, below the room's floor (z 0)
SURFACE = -8   # the liquid's top


def pool(x0, x1, y0, y1, liquid):
    """A pit x0..x1, y0..y1 in the floor, its floor poolfloor, filled with `liquid` (or dry)."""
    brushes = [box((x0, y0, -DEPTH - T), (x1, y1, -DEPTH), "poolfloor")]
    if liquid:
        brushes.append(box((x0, y0, -DEPTH), (x1, y1, SURFACE), liquid))
    return brushes


def floor_around(pits):
    """The room's floor (z -DEPTH-T..0) with holes: one slab per gap between pits along y."""
    x0, x1 = pits[0][0], pits[0][1]
    brushes = [box((X0 - T, Y0 - T, -DEPTH - T), (x0, Y1 + T, 0), "floor"),
               box((x1, Y0 - T, -DEPTH - T), (X1 + T, Y1 + T, 0), "floor")]
    y = Y0 - T
    for (_, _, py0, py1) in sorted(pits, key=lambda p: p[2]):
        brushes.append(box((x0, y, -DEPTH - T), (x1, py0, 0), "poolwall"))
        y = py1
    brushes.append(box((x0, y, -DEPTH - T), (x1, Y1 + T, 0), "poolwall"))
    return brushes


def room():
    return [
        box((X0 - T, Y0 - T, Z1), (X1 + T, Y1 + T, Z1 + T), "white"),
        box((X0 - T, Y0 - T, 0), (X0, Y1 + T, Z1), "bricks"),
        box((X1, Y0 - T, 0), (X1 + T, Y1 + T, Z1), "bricks"),
        box((X0, Y0 - T, 0), (X1, Y0, Z1), "bricks"),
        box((X0, Y1, 0), (X1, Y1 + T, Z1), "bricks"),
    ]


def write_map(name, world_keys, brushes, lights, camera, message):
    ents = [entity([("classname", "worldspawn"), ("mapversion", "220"), ("message", message)] + world_keys, brushes),
            entity([("classname", "info_player_start"), ("origin", "-200 0 24"), ("angle", "0")]),
            entity([("classname", "info_intermission"), ("origin", camera[0]), ("mangle", camera[1])])]
    ents += [entity([("classname", "light"), ("origin", o), ("light", str(v))]) for o, v in lights]
    with open(os.path.join(HERE, name), "w") as f:
        f.write("// Game: Quake\n// Format: Valve\n// Written by maps/liquids/generate.py\n")
        f.write("\n".join(ents) + "\n")


def main():
    pit = (0, 128, -64, 64)
    one = floor_around([pit]) + room()
    camera = ("-96 0 128", "45 0 0")
    lights = [("64 0 160", 300)]
    write_map("pool.map", [("_wateralpha", "0.5")], one + pool(*pit, "*water_blue"), lights, camera,
              "liquids: water at _wateralpha 0.5 over a yellow floor")
    write_map("pool_opaque.map", [], one + pool(*pit, "*water_blue"), lights, camera, "liquids: opaque water")
    write_map("pool_dry.map", [], one + pool(*pit, None), lights, camera, "liquids: the pool without its water")

    pits = [(0, 128, -176, -64, "*water_blue"), (0, 128, -56, 56, "*slime_green"), (0, 128, 64, 176, "*lava_glow")]
    brushes = floor_around([p[:4] for p in pits]) + room()
    for p in pits:
        brushes += pool(*p)
    # A dark wall beside the lava, for its emission to light.
    brushes.append(box((144, 64, 0), (160, 176, 96), "poolwall"))
    lights = [(f"{x} {y} 160", 300) for x in (-128, 64) for y in (-120, 120)]
    write_map("pools.map", [], brushes, lights, ("-160 0 160", "40 0 0"),
              "liquids: water, slime and lava")
    lava = (0, 128, 64, 176, "*lava_glow")
    brushes = floor_around([lava[:4]]) + room() + pool(*lava)
    brushes.append(box((144, 64, 0), (160, 176, 96), "poolwall"))
    write_map("lava_dark.map", [], brushes, [], ("-96 120 96", "30 0 0"),
              "liquids: lava beside a wall, no light")
    halves = [box((0, -64, -DEPTH), (96, 64, SURFACE), "*water_blue"), box((32, -64, -DEPTH), (128, 64, SURFACE), "*water_blue"),
              box((48, -32, -48), (80, 32, -24), "*water_blue")]
    write_map("csg_water.map", [("_wateralpha", "0.5")], one + pool(*pit, None) + halves, lights, camera,
              "liquids: pool.map's water in three overlapping brushes")
    write_map("csg_lava.map", [("_wateralpha", "0.5"), ("_lavaalpha", "0.5")],
              one + pool(*pit, "*lava_glow") + [box((32, -32, -48), (96, 32, -24), "*water_blue")], lights, camera,
              "liquids: a water box inside lava")
    os.makedirs(os.path.join(HERE, "textures"), exist_ok=True)
    for name, rgb in COLOURS.items():
        write_png(os.path.join(HERE, "textures", name + ".png"), 16, 16, lambda x, y, c=rgb: c)


if __name__ == "__main__":
    main()
