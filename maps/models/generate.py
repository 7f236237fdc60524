"""Writes oa_items.map, the entity-model test level (tests/gl/gl_entity_models_test.cpp): a small
Quake 3 room (textures from maps/textures/) with an item_health and a weapon_rocketlauncher in
front of the deathmatch spawn, lit by one light. Rendered with `--game quake3 --basedir
/usr/share/games/openarena` (Debian's openarena-085-data) the items show OpenArena's models
(bg_misc.c: models/powerups/health/medium_cross.md3, models/weapons2/rocketl/rocketl.md3).
Run it again after editing; the output is deterministic. Needs only the standard library.
"""
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def box(lo, hi, texture):
    """An axial box in Quake 3's legacy brush format (three points per plane, normal outward)."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    planes = [
        ((x0, y0, z0), (x0, y1, z0), (x0, y0, z1)),  # -x
        ((x0, y0, z0), (x0, y0, z1), (x1, y0, z0)),  # -y
        ((x0, y0, z0), (x1, y0, z0), (x0, y1, z0)),  # -z
        ((x1, y1, z1), (x1, y0, z1), (x0, y1, z1)),  # +z
        ((x1, y1, z1), (x0, y1, z1), (x1, y1, z0)),  # +y
        ((x1, y1, z1), (x1, y1, z0), (x1, y0, z1)),  # +x
    ]
    lines = ["{"]
    for p in planes:
        pts = " ".join("( %g %g %g )" % q for q in p)
        lines.append(f"{pts} {texture} 0 0 0 0.5 0.5 0 0 0")
    lines.append("}")
    return "\n".join(lines)


def entity(keys, brushes=()):
    body = "\n".join(f'"{k}" "{v}"' for k, v in keys)
    return "{\n" + body + ("\n" + "\n".join(brushes) if brushes else "") + "\n}"


def main():
    T = 16
    x0, x1, y0, y1, z0, z1 = -192, 192, -128, 128, 0, 160
    room = [
        box((x0 - T, y0 - T, z0 - T), (x1 + T, y1 + T, z0), "floor"),
        box((x0 - T, y0 - T, z1), (x1 + T, y1 + T, z1 + T), "white"),
        box((x0 - T, y0 - T, z0), (x0, y1 + T, z1), "redwall"),
        box((x1, y0 - T, z0), (x1 + T, y1 + T, z1), "greenwall"),
        box((x0, y0 - T, z0), (x1, y0, z1), "bricks"),
        box((x0, y1, z0), (x1, y1 + T, z1), "bricks"),
    ]
    ents = [
        entity([("classname", "worldspawn"), ("message", "entity models: OpenArena items")], room),
        entity([("classname", "info_player_deathmatch"), ("origin", "-96 0 24"), ("angle", "0")]),
        entity([("classname", "item_health"), ("origin", "0 -16 32")]),
        entity([("classname", "weapon_rocketlauncher"), ("origin", "0 24 32"), ("angle", "90")]),
        entity([("classname", "light"), ("origin", "-64 0 128"), ("light", "400")]),
    ]
    header = ("// Game: Quake 3\n// Format: Quake3 (legacy)\n// Written by maps/models/generate.py: OpenArena's item models at "
              "point entities\n")
    with open(os.path.join(HERE, "oa_items.map"), "w") as f:
        f.write(header + "\n".join(ents) + "\n")


if __name__ == "__main__":
    main()
