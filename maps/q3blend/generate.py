"""Writes the Quake 3 blend test level (tests/render/q3_blends_test.cpp, tests/gl/gl_liquids_test.cpp),
laid out as a Quake 3 game folder: maps/, scripts/blends.shader, textures/blend/.

- maps/blends.map: a lit room whose back wall (`blend/wall`, one flat colour) is seen through three
  panels side by side, each a brush whose face towards the camera has a blended shader and whose
  other faces are `common/caulk` (hidden): `blend/add` (blendFunc add), `blend/filter` (blendFunc
  GL_DST_COLOR GL_ZERO) and `blend/blend` (blendFunc blend, its image's alpha 128 everywhere).
- maps/blends_behind.map: the same room without the panels: what lies behind them.
The engine draws each panel over blends_behind.map's pixel: add = behind + image, filter =
behind x image, blend = alpha x image + (1 - alpha) x behind, in its framebuffer's gamma space.
Run it again after editing; the output is deterministic. Needs only the standard library.
"""
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))

# Flat colours (sRGB bytes, and alpha), so that each blend is a number the tests can compute.
IMAGES = {
    "wall": (200, 160, 80, 255),
    "floor": (110, 110, 120, 255),
    "add": (40, 30, 60, 255),
    "filter": (180, 220, 120, 255),
    "blend": (50, 200, 90, 128),
}

SHADERS = """// The shaders of maps/q3blend/maps/blends.map (written by maps/q3blend/generate.py): each one
// stage, drawn over what lies behind with its blendFunc, as ioquake3 draws it.

textures/blend/add
{
	surfaceparm trans
	surfaceparm nolightmap
	{
		map textures/blend/add.png
		blendFunc add
	}
}

textures/blend/filter
{
	surfaceparm trans
	surfaceparm nolightmap
	{
		map textures/blend/filter.png
		blendFunc GL_DST_COLOR GL_ZERO
	}
}

textures/blend/blend
{
	surfaceparm trans
	surfaceparm nolightmap
	{
		map textures/blend/blend.png
		blendFunc blend
	}
}
"""


def write_rgba_png(path, size, rgba):
    """A size x size PNG of one RGBA colour (colour type 6)."""
    rows = b"".join(b"\x00" + bytes(rgba) * size for _ in range(size))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", size, size, 8, 6, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def box(lo, hi, texture, front=None):
    """An axial box in Quake 3's legacy brush format; `front` textures its -x face."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    planes = [  # three points each, in the order maps/dialects/quake3.map has them
        ((x0, y0, z0), (x0, y1, z0), (x0, y0, z1), front or texture),  # -x
        ((x1, y1, z1), (x1, y1, z0), (x1, y0, z1), texture),            # +x
        ((x0, y0, z0), (x0, y0, z1), (x1, y0, z0), texture),            # -y
        ((x1, y1, z1), (x0, y1, z1), (x1, y1, z0), texture),            # +y
        ((x0, y0, z0), (x1, y0, z0), (x0, y1, z0), texture),            # -z
        ((x1, y1, z1), (x1, y0, z1), (x0, y1, z1), texture),            # +z
    ]
    lines = ["{"]
    for a, b, c, tex in planes:
        pts = " ".join("( %g %g %g )" % p for p in (a, b, c))
        lines.append(f"{pts} {tex} 0 0 0 0.5 0.5 0 0 0")
    lines.append("}")
    return "\n".join(lines)


def entity(keys, brushes=()):
    body = "\n".join(f'"{k}" "{v}"' for k, v in keys)
    return "{\n" + body + ("\n" + "\n".join(brushes) if brushes else "") + "\n}"


PANELS = [("blend/add", -100), ("blend/filter", 0), ("blend/blend", 100)]


def room():
    T = 16
    x0, x1, y0, y1, z1 = -192, 256, -192, 192, 192
    return [
        box((x0 - T, y0 - T, -T), (x1 + T, y1 + T, 0), "blend/floor"),
        box((x0 - T, y0 - T, z1), (x1 + T, y1 + T, z1 + T), "blend/floor"),
        box((x1, y0, 0), (x1 + T, y1, z1), "blend/wall"),
        box((x0 - T, y0, 0), (x0, y1, z1), "blend/floor"),
        box((x0 - T, y0 - T, 0), (x1 + T, y0, z1), "blend/floor"),
        box((x0 - T, y1, 0), (x1 + T, y1 + T, z1), "blend/floor"),
    ]


def write_map(name, with_panels, message):
    brushes = room()
    if with_panels:
        brushes += [box((96, y - 40, 24), (100, y + 40, 104), "common/caulk", front=tex) for tex, y in PANELS]
    ents = [entity([("classname", "worldspawn"), ("message", message)], brushes),
            entity([("classname", "info_player_deathmatch"), ("origin", "-96 0 29"), ("angle", "0")]),
            entity([("classname", "light"), ("origin", "0 0 180"), ("light", "500")])]
    with open(os.path.join(HERE, "maps", name), "w") as f:
        f.write("// Game: Quake 3\n// Format: Quake3 (legacy)\n// Written by maps/q3blend/generate.py\n")
        f.write("\n".join(ents) + "\n")


def main():
    for folder in ("maps", "scripts", os.path.join("textures", "blend")):
        os.makedirs(os.path.join(HERE, folder), exist_ok=True)
    for name, rgba in IMAGES.items():
        write_rgba_png(os.path.join(HERE, "textures", "blend", name + ".png"), 16, rgba)
    with open(os.path.join(HERE, "scripts", "blends.shader"), "w") as f:
        f.write(SHADERS)
    write_map("blends.map", True, "three blended panels before a wall")
    write_map("blends_behind.map", False, "the wall without the panels")


if __name__ == "__main__":
    main()
