#!/usr/bin/env python3
"""Writes the project's own small procedural textures into this folder.

    python3 assets/textures/make_textures.py

bricks_height.png: a 128x128 8-bit grey height map of running-bond bricks (4 courses of 2 bricks,
every other course shifted by half a brick), bricks high (about 0.8..1, slightly rough) with
bevelled edges, mortar joints low (0). It tiles seamlessly. Read it as linear data ("colorspace": "linear"); the
reference scene tests/reference_images/scenes/bump_wall.json bump-maps a wall with it.

Pure Python (zlib + struct): no third-party modules, and the output is byte-identical on every
machine, so re-running the script does not change the committed file.
"""
import os
import struct
import zlib

SIZE = 128          # pixels per side
COURSES = 4         # brick rows
BRICKS = 2          # bricks per row
MORTAR = 6          # joint width in pixels
BEVEL = 5           # pixels over which a brick edge rises from the joint to its top
GRAIN = 8           # period (pixels) of the rough brick surface
ROUGH = 0.08        # its amplitude


def hash01(*values):
    """A deterministic value in [0, 1) from integers (no random module: fixed across Pythons)."""
    h = 2166136261
    for v in values:
        for byte in struct.pack("<i", v):
            h = ((h ^ byte) * 16777619) & 0xFFFFFFFF
    h ^= h >> 15
    h = (h * 0x2C1B3C6D) & 0xFFFFFFFF
    h ^= h >> 12
    return h / 2**32


def grain(x, y):
    """Smooth value noise of period GRAIN that tiles over SIZE (bilinear, smoothstep-eased)."""
    cells = SIZE // GRAIN
    gx, gy = x / GRAIN, y / GRAIN
    ix, iy = int(gx), int(gy)
    fx, fy = gx - ix, gy - iy
    fx, fy = fx * fx * (3 - 2 * fx), fy * fy * (3 - 2 * fy)

    def at(i, j):
        return hash01(1000 + i % cells, 2000 + j % cells)

    top = at(ix, iy) * (1 - fx) + at(ix + 1, iy) * fx
    bottom = at(ix, iy + 1) * (1 - fx) + at(ix + 1, iy + 1) * fx
    return top * (1 - fy) + bottom * fy


def brick_height(x, y):
    course_h = SIZE // COURSES
    brick_w = SIZE // BRICKS
    course = y // course_h
    shift = (brick_w // 2) if course % 2 else 0
    bx = (x + shift) % SIZE
    brick = bx // brick_w
    # Distance (pixels) from this pixel to the nearest joint centre line, minus half a joint.
    ly = y % course_h + 0.5
    lx = bx % brick_w + 0.5
    d = min(ly, course_h - ly, lx, brick_w - lx) - MORTAR / 2
    if d <= 0:
        return 0.0
    top = 0.8 + 0.12 * hash01(course, brick)  # each brick a little higher or lower
    top += ROUGH * grain(x + 0.5, y + 0.5)    # and a little rough
    t = min(1.0, d / BEVEL)
    t = t * t * (3 - 2 * t)  # smooth rounded edge
    return top * t


def write_grey_png(path, width, height, rows):
    """8-bit greyscale PNG; each row uses the 'up' filter, which suits smooth images."""
    raw = bytearray()
    previous = bytes(width)
    for row in rows:
        raw.append(2)  # filter type: up
        raw.extend((row[i] - previous[i]) & 0xFF for i in range(width))
        previous = row

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(bytes(raw), 9))
    png += chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def main():
    folder = os.path.dirname(os.path.abspath(__file__))
    rows = [bytes(round(255 * brick_height(x, y)) for x in range(SIZE)) for y in range(SIZE)]
    path = os.path.join(folder, "bricks_height.png")
    write_grey_png(path, SIZE, SIZE, rows)
    print("wrote", path, os.path.getsize(path), "bytes")


if __name__ == "__main__":
    main()
