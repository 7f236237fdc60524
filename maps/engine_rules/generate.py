"""Writes the maps of the engine-rule tests (tests/render/engine_rules_test.cpp, tests/gl):
each pair is a level with something the game hides or cuts and the level as the engine shows it.

- hidden.map: a room with a trigger_multiple (textured `bricks`, `_shadow 1`), a
  func_episodegate and a `*waterskip` brush between the player start and a light;
  hidden_reference.map: the same room without them. The game draws neither, and the compiler
  lights neither, so both render the same image.
- fence.map: a room split by a `{fence` wall (an 8-bit colour-mapped PNG in LibreQuake's manner:
  palette index 255 is see-through; its colour here is not Quake's 255, so only the index tells)
  with the only light behind it; fence_open.map: the room without the fence.
Run it again after editing; the output is deterministic. Needs only the standard library.
"""
import os
import struct
import sys
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
from generate_start import box, entity  # noqa: E402

FENCE_SIZE = 64
BAR = 8      # opaque bars FENCE_BAR texels wide every FENCE_PERIOD texels, both ways
PERIOD = 32


def fence_index(x, y):
    return 1 + (x + y) % 8 if x % PERIOD < BAR or y % PERIOD < BAR else 255


def write_paletted_png(path, width, height, index, palette):
    rows = b"".join(b"\x00" + bytes(index(x, y) for x in range(width)) for y in range(height))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 3, 0, 0, 0))
    png += chunk(b"PLTE", bytes(c for rgb in palette for c in rgb))
    png += chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def room():
    T = 16
    x0, x1, y0, y1, z0, z1 = -256, 256, -128, 128, 0, 192
    return [
        box((x0 - T, y0 - T, z0 - T), (x1 + T, y1 + T, z0), "floor"),
        box((x0 - T, y0 - T, z1), (x1 + T, y1 + T, z1 + T), "white"),
        box((x0 - T, y0 - T, z0), (x0, y1 + T, z1), "redwall"),
        box((x1, y0 - T, z0), (x1 + T, y1 + T, z1), "greenwall"),
        box((x0, y0 - T, z0), (x1, y0, z1), "bricks"),
        box((x0, y1, z0), (x1, y1 + T, z1), "bricks"),
    ]


def write_map(name, world_brushes, more_entities, message):
    ents = [entity([("classname", "worldspawn"), ("mapversion", "220"), ("message", message), ("light", "0")],
                   world_brushes),
            entity([("classname", "info_player_start"), ("origin", "-200 0 24"), ("angle", "0")]),
            entity([("classname", "light"), ("origin", "150 0 96"), ("light", "600")])]
    ents += more_entities
    with open(os.path.join(HERE, name), "w") as f:
        f.write("// Game: Quake\n// Format: Valve\n// Written by maps/engine_rules/generate.py\n")
        f.write("\n".join(ents) + "\n")


def main():
    # The hidden things come last, so the faces of both maps share their indices.
    hidden = [
        entity([("classname", "trigger_multiple"), ("_shadow", "1")], [box((-32, -64, 0), (32, 64, 128), "bricks")]),
        entity([("classname", "func_episodegate"), ("spawnflags", "1")], [box((60, 40, 0), (100, 100, 150), "bricks")]),
    ]
    write_map("hidden.map", room() + [box((60, -100, 0), (120, -40, 40), "*waterskip")], hidden,
              "engine rules: what the game hides")
    write_map("hidden_reference.map", room(), [], "engine rules: what the game hides, as the game shows it")
    write_map("fence.map", room() + [box((0, -128, 0), (8, 128, 192), "{fence")], [], "engine rules: a PNG fence")
    write_map("fence_open.map", room(), [], "engine rules: a PNG fence, without it")
    os.makedirs(os.path.join(HERE, "textures"), exist_ok=True)
    palette = [(40 + 20 * (i % 8), 70 + 10 * (i % 8), 60) for i in range(255)] + [(0, 255, 0)]
    write_paletted_png(os.path.join(HERE, "textures", "{fence.png"), FENCE_SIZE, FENCE_SIZE, fence_index, palette)


if __name__ == "__main__":
    main()
