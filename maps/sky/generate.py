"""Writes the level of the sky tests (tests/render/sky_test.cpp, tests/gl/gl_sky_test.cpp):

- sky_layers.map: a 512 x 512 x 256 room whose ceiling is Quake sky (`sky_test`), lit by one light,
  its info_intermission (the default camera) looking up at the sky.
- sky_layers.wad: a WAD2 with the textures and its own palette lump: `sky_test`, 256 x 128 as
  Quake's skies are, its right half the back layer (a checker of two blues in 16-texel cells), its
  left half the front layer (red bars 8 texels wide every 32 texels, yellow bars 4 texels high
  every 32 texels, palette index 0 between them: clear); `wall`, grey.
- id1/maps/sky_box.map: a room of sky on all six sides around a grey pillar, with `"sky" "testsky"`;
  it lies in a Quake game folder (id1/), whose gfx/env/ holds the sky box: testsky{rt,bk,lf,ft,up,dn}.tga,
  8 x 8, each one colour (rt red, bk green, lf blue, ft yellow, up cyan, dn magenta) with its top
  left quarter white, so that a side in the wrong place or turned shows.
The palette is the test's own (index 0 black, as Quake's), so each colour tells where it came from.
Run it again after editing; the output is deterministic. Needs only the standard library.
"""
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
from generate_start import box, entity  # noqa: E402

PALETTE = [(0, 0, 0), (40, 60, 200), (170, 190, 250), (220, 40, 30), (230, 200, 20), (128, 128, 128)]
PALETTE += [(i, i, i) for i in range(len(PALETTE), 256)]


def sky_index(x, y):
    if x >= 128:  # back layer: a checker of 16-texel cells
        return 1 if ((x - 128) // 16 + y // 16) % 2 == 0 else 2
    if x % 32 < 8:
        return 3
    if y % 32 < 4:
        return 4
    return 0


def miptex(name, width, height, index):
    pixels = bytes(index(x, y) for y in range(height) for x in range(width))
    mips, offsets, at = [], [], 40
    for level in range(4):  # the smaller mips: every 2^level-th texel (unused by the importer)
        step = 1 << level
        mip = bytes(pixels[y * width + x] for y in range(0, height, step) for x in range(0, width, step))
        offsets.append(at)
        at += len(mip)
        mips.append(mip)
    return name.encode().ljust(16, b"\0") + struct.pack("<6I", width, height, *offsets) + b"".join(mips)


def write_wad(path, lumps):
    """lumps: (name, type, bytes)."""
    data, directory, at = b"", b"", 12
    for name, kind, blob in lumps:
        directory += struct.pack("<3I4B", at, len(blob), len(blob), kind, 0, 0, 0) + name.encode().ljust(16, b"\0")
        data += blob
        at += len(blob)
    with open(path, "wb") as f:
        f.write(b"WAD2" + struct.pack("<2I", len(lumps), at) + data + directory)


def write_map(path):
    T = 16
    x0, x1, y0, y1, z0, z1 = -256, 256, -256, 256, 0, 256
    brushes = [
        box((x0 - T, y0 - T, z0 - T), (x1 + T, y1 + T, z0), "wall"),
        box((x0 - T, y0 - T, z1), (x1 + T, y1 + T, z1 + T), "sky_test"),
        box((x0 - T, y0 - T, z0), (x0, y1 + T, z1), "wall"),
        box((x1, y0 - T, z0), (x1 + T, y1 + T, z1), "wall"),
        box((x0, y0 - T, z0), (x1, y0, z1), "wall"),
        box((x0, y1, z0), (x1, y1 + T, z1), "wall"),
    ]
    ents = [entity([("classname", "worldspawn"), ("mapversion", "220"), ("wad", "sky_layers.wad"),
                    ("message", "Quake's two-layer sky")], brushes),
            # The default camera: looking up into the sky, from the horizon's edge to near the zenith.
            entity([("classname", "info_intermission"), ("origin", "0 0 64"), ("mangle", "-50 30 0")]),
            entity([("classname", "info_player_start"), ("origin", "0 0 24"), ("angle", "0")]),
            entity([("classname", "light"), ("origin", "0 0 128"), ("light", "300")])]
    with open(path, "w") as f:
        f.write("// Written by generate.py.\n" + "\n".join(ents) + "\n")


SIDES = {"rt": (200, 0, 0), "bk": (0, 200, 0), "lf": (0, 0, 200), "ft": (200, 200, 0), "up": (0, 200, 200), "dn": (200, 0, 200)}


def write_tga(path, size, colour):
    """Uncompressed 24-bit, rows top to bottom (descriptor bit 5); the top left quarter white."""
    header = struct.pack("<BBBHHBHHHHBB", 0, 0, 2, 0, 0, 0, 0, 0, size, size, 24, 0x20)
    rows = b""
    for y in range(size):
        for x in range(size):
            r, g, b = (255, 255, 255) if x < size // 2 and y < size // 2 else colour
            rows += bytes((b, g, r))
    with open(path, "wb") as f:
        f.write(header + rows)


def write_sky_box_level(install):
    os.makedirs(os.path.join(install, "id1", "maps"), exist_ok=True)
    os.makedirs(os.path.join(install, "id1", "gfx", "env"), exist_ok=True)
    for suffix, colour in SIDES.items():
        write_tga(os.path.join(install, "id1", "gfx", "env", "testsky" + suffix + ".tga"), 8, colour)
    T, R = 16, 256
    brushes = [
        box((-R - T, -R - T, -R - T), (R + T, R + T, -R), "sky_test"),
        box((-R - T, -R - T, R), (R + T, R + T, R + T), "sky_test"),
        box((-R - T, -R - T, -R), (-R, R + T, R), "sky_test"),
        box((R, -R - T, -R), (R + T, R + T, R), "sky_test"),
        box((-R, -R - T, -R), (R, -R, R), "sky_test"),
        box((-R, R, -R), (R, R + T, R), "sky_test"),
        box((-16, -16, -R), (16, 16, -128), "wall"),
    ]
    ents = [entity([("classname", "worldspawn"), ("mapversion", "220"), ("wad", "../../sky_layers.wad"), ("sky", "testsky"),
                    ("message", "A sky box")], brushes),
            entity([("classname", "info_player_start"), ("origin", "0 0 0"), ("angle", "0")])]
    with open(os.path.join(install, "id1", "maps", "sky_box.map"), "w") as f:
        f.write("// Written by ../../generate.py.\n" + "\n".join(ents) + "\n")


write_sky_box_level(HERE)
write_wad(os.path.join(HERE, "sky_layers.wad"), [
    ("palette", 0x40, bytes(c for rgb in PALETTE for c in rgb)),
    ("sky_test", 0x44, miptex("sky_test", 256, 128, sky_index)),
    ("wall", 0x44, miptex("wall", 16, 16, lambda x, y: 5)),
])
write_map(os.path.join(HERE, "sky_layers.map"))
