#!/usr/bin/env python3
"""Writes maps/start.map (Valve 220) and the small PNG textures in maps/textures/ it uses.

The default level of `brushtrace render`: one room that shows every light type the renderer
knows - a point light, an inverse-square coloured light, a spotlight aimed at a target, a sun
and a sky dome through a skylight, a `_surface` area light on an emissive (`_glow`) panel,
worldspawn minlight - plus red and green walls for coloured bounce and a pool of water.
Run it again after editing; the output is deterministic. Needs only the standard library.
"""
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


# --- textures ---------------------------------------------------------------------------------

def write_png(path, width, height, pixel):
    """pixel(x, y) -> (r, g, b); 8-bit RGB PNG."""
    rows = b"".join(b"\x00" + bytes(c for x in range(width) for c in pixel(x, y)) for y in range(height))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def noise(x, y, seed):
    h = (x * 374761393 + y * 668265263 + seed * 2147483647) & 0xFFFFFFFF
    h = ((h ^ (h >> 13)) * 1274126177) & 0xFFFFFFFF
    return ((h ^ (h >> 16)) & 0xFF) / 255.0


def shade(rgb, k):
    return tuple(max(0, min(255, int(c * k))) for c in rgb)


def bricks(x, y):
    row = y // 16
    offset = 16 if row % 2 else 0
    mortar = y % 16 == 0 or (x + offset) % 32 == 0
    base = (150, 130, 110) if not mortar else (90, 85, 80)
    return shade(base, 0.85 + 0.3 * noise(x // 2, y // 2, 1))


def floor_tiles(x, y):
    checker = ((x // 32) + (y // 32)) % 2
    base = (120, 120, 115) if checker else (160, 155, 140)
    if x % 32 == 0 or y % 32 == 0:
        base = (70, 70, 70)
    return shade(base, 0.9 + 0.2 * noise(x, y, 2))


def plaster(rgb, seed):
    return lambda x, y: shade(rgb, 0.9 + 0.2 * noise(x // 2, y // 2, seed))


def sky(x, y):
    cloud = 0.5 + 0.5 * math.sin(x * 0.2) * math.cos(y * 0.15)
    return shade((90, 140, 220), 0.85 + 0.3 * cloud * noise(x // 4, y // 4, 3))


def lamp(x, y):
    frame = x < 4 or x >= 60 or y < 4 or y >= 28
    return (60, 60, 70) if frame else (255, 240, 200)


def lamp_glow(x, y):
    frame = x < 4 or x >= 60 or y < 4 or y >= 28
    return (0, 0, 0) if frame else (255, 235, 190)


def water(x, y):
    return shade((40, 90, 110), 0.85 + 0.3 * (0.5 + 0.5 * math.sin((x + y) * 0.3)))


def write_textures():
    out = os.path.join(HERE, "textures")
    os.makedirs(out, exist_ok=True)
    write_png(os.path.join(out, "bricks.png"), 64, 64, bricks)
    write_png(os.path.join(out, "floor.png"), 64, 64, floor_tiles)
    write_png(os.path.join(out, "redwall.png"), 32, 32, plaster((190, 40, 35), 4))
    write_png(os.path.join(out, "greenwall.png"), 32, 32, plaster((40, 160, 60), 5))
    write_png(os.path.join(out, "white.png"), 32, 32, plaster((220, 220, 215), 6))
    write_png(os.path.join(out, "sky1.png"), 64, 64, sky)
    write_png(os.path.join(out, "lamp.png"), 64, 32, lamp)
    write_png(os.path.join(out, "lamp_glow.png"), 64, 32, lamp_glow)
    write_png(os.path.join(out, "star_water.png"), 64, 64, water)  # '*water' on disk


# --- map --------------------------------------------------------------------------------------

# Three plane points per outward normal: qbsp's normal is cross(p0 - p1, p2 - p1).
# A, B with cross(A, B) = n; p1 = p0 - A, p2 = p1 + B.
AXES = {
    (1, 0, 0): ((0, 1, 0), (0, 0, 1)), (-1, 0, 0): ((0, 0, 1), (0, 1, 0)),
    (0, 1, 0): ((0, 0, 1), (1, 0, 0)), (0, -1, 0): ((1, 0, 0), (0, 0, 1)),
    (0, 0, 1): ((1, 0, 0), (0, 1, 0)), (0, 0, -1): ((0, 1, 0), (1, 0, 0)),
}
# Valve 220 texture axes per face orientation (TrenchBroom's defaults for axial faces).
TEX_AXES = {0: ("[ 0 1 0 0 ]", "[ 0 0 -1 0 ]"), 1: ("[ 1 0 0 0 ]", "[ 0 0 -1 0 ]"), 2: ("[ 1 0 0 0 ]", "[ 0 -1 0 0 ]")}


def box(lo, hi, texture, textures=None):
    """An axial box brush; `textures` overrides per normal, e.g. {(0, 0, -1): 'lamp'}."""
    lines = ["{"]
    for n, (a, b) in AXES.items():
        axis = [i for i in range(3) if n[i]][0]
        p0 = [lo[0], lo[1], lo[2]]
        p0[axis] = hi[axis] if n[axis] > 0 else lo[axis]
        p1 = [p0[i] - 64 * a[i] for i in range(3)]
        p2 = [p1[i] + 64 * b[i] for i in range(3)]
        tex = (textures or {}).get(n, texture)
        u, v = TEX_AXES[axis]
        pts = " ".join("( %g %g %g )" % tuple(p) for p in (p0, p1, p2))
        lines.append(f"{pts} {tex} {u} {v} 0 1 1")
    lines.append("}")
    return "\n".join(lines)


def entity(keys, brushes=()):
    body = "\n".join(f'"{k}" "{v}"' for k, v in keys)
    return "{\n" + body + ("\n" + "\n".join(brushes) if brushes else "") + "\n}"


def write_map():
    T = 16  # wall thickness
    x0, x1, y0, y1, z0, z1 = -256, 256, -192, 192, 0, 192
    # The skylight: a 128 x 128 hole in the ceiling with a sky-lined shaft above it.
    hx0, hx1, hy0, hy1 = 32, 160, -64, 64
    brushes = [
        box((x0 - T, y0 - T, z0 - T), (x1 + T, y1 + T, z0), "floor"),
        box((x0 - T, y0 - T, z0), (x0, y1 + T, z1), "redwall"),          # west: red
        box((x1, y0 - T, z0), (x1 + T, y1 + T, z1), "greenwall"),        # east: green
        box((x0, y0 - T, z0), (x1, y0, z1), "bricks"),                   # south
        box((x0, y1, z0), (x1, y1 + T, z1), "bricks"),                   # north
        # ceiling around the hole
        box((x0 - T, y0 - T, z1), (hx0, y1 + T, z1 + T), "white"),
        box((hx1, y0 - T, z1), (x1 + T, y1 + T, z1 + T), "white"),
        box((hx0, y0 - T, z1), (hx1, hy0, z1 + T), "white"),
        box((hx0, hy1, z1), (hx1, y1 + T, z1 + T), "white"),
        # sky shaft above the hole: its inner faces are sky
        box((hx0 - T, hy0 - T, z1 + T), (hx0, hy1 + T, z1 + 96), "sky1"),
        box((hx1, hy0 - T, z1 + T), (hx1 + T, hy1 + T, z1 + 96), "sky1"),
        box((hx0, hy0 - T, z1 + T), (hx1, hy0, z1 + 96), "sky1"),
        box((hx0, hy1, z1 + T), (hx1, hy1 + T, z1 + 96), "sky1"),
        box((hx0 - T, hy0 - T, z1 + 96), (hx1 + T, hy1 + T, z1 + 96 + T), "sky1"),
        # a white pillar in the sunbeam's way, and a low block for the spotlight
        box((-32, -32, z0), (0, 0, 128), "white"),
        box((120, 96, z0), (184, 160, 32), "bricks"),
        # the emissive panel on the north wall (a _surface area light)
        box((-160, y1 - 4, 96), (-96, y1, 128), "bricks", {(0, -1, 0): "lamp"}),
        # a pool of water in the south-west corner, flush with a low rim
        box((-240, -176, z0), (-144, -112, 8), "*water"),
    ]
    world = entity([
        ("classname", "worldspawn"),
        ("mapversion", "220"),
        ("message", "brushtrace start: every light type"),
        ("_sunlight", "220"), ("_sun_mangle", "30 -60 0"), ("_sunlight_color", "255 240 210"),
        ("_sunlight_penumbra", "2"),
        ("_sunlight2", "40"), ("_sunlight2_color", "150 180 255"),
        ("light", "8"),          # minlight
        ("_bounce", "1"),
    ], brushes)
    ents = [
        world,
        entity([("classname", "info_player_start"), ("origin", "-200 -140 24"), ("angle", "35")]),
        entity([("classname", "info_intermission"), ("origin", "236 -176 160"), ("mangle", "24 148 0")]),
        entity([("classname", "light"), ("origin", "-180 40 120"), ("light", "200")]),
        entity([("classname", "light"), ("origin", "200 -120 100"), ("light", "140"), ("delay", "2"),
                ("_color", "255 150 60")]),
        entity([("classname", "light_spot"), ("origin", "152 128 180"), ("light", "400"), ("target", "spot1"),
                ("angle", "50"), ("_softangle", "25"), ("_color", "120 160 255")]),
        entity([("classname", "info_null"), ("origin", "152 128 32"), ("targetname", "spot1")]),
        entity([("classname", "light"), ("origin", "-128 180 112"), ("_surface", "lamp"), ("light", "120")]),
    ]
    with open(os.path.join(HERE, "start.map"), "w") as f:
        f.write("// Game: Quake\n// Format: Valve\n// Written by maps/generate_start.py\n")
        for i, e in enumerate(ents):
            f.write(f"// entity {i}\n{e}\n")


if __name__ == "__main__":
    write_textures()
    write_map()
