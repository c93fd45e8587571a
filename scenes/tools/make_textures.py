#!/usr/bin/env python3
"""Writes the procedural textures of the textured scenes, and two tiny test textures, as PNGs.

Textures (all 8-bit, no alpha):

- spots_shininess.png  256x256 grey: a few dozen round spots of high value (high Blinn-Phong
  shininess) with soft edges 4 to 8 texels wide, on a low background; tileable in u and v.
- spots_albedo.png     256x256 RGB: the same spots in a different hue from the skin.
- fabric_roughness.png 256x256 grey: woven fabric, checks of rough (high value) and smoother
  (low value) bands with smooth transitions, and a fine thread weave; tileable.
- fabric_albedo.png    256x256 RGB: the matching two-tone fabric colour.
- checker_8.png        8x8 grey: a hard one-texel checker, 0 where x + y is even, 255 elsewhere.
- one_texel.png        1x1 grey: one texel of value 200.

The spot layout comes from a fixed linear congruential generator, so every run writes the same
bytes. Standard library only (zlib and struct write the PNGs).

Usage:
    python3 scenes/tools/make_textures.py scenes/textures
"""

import math
import struct
import sys
import zlib
from pathlib import Path

SIZE = 256


def png(width: int, height: int, channels: int, rows: list) -> bytes:
    """An 8-bit grey (channels 1) or RGB (channels 3) PNG; rows are bytes of width*channels."""
    colour_type = {1: 0, 3: 2}[channels]

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    header = struct.pack(">IIBBBBB", width, height, 8, colour_type, 0, 0, 0)
    raw = b"".join(b"\x00" + bytes(row) for row in rows)  # filter type 0 (None) on every row
    idat = zlib.compress(raw, 9)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", idat) + chunk(b"IEND", b"")


def to_byte(v: float) -> int:
    return max(0, min(255, int(math.floor(v * 255.0 + 0.5))))


def smoothstep(edge0: float, edge1: float, x: float) -> float:
    t = max(0.0, min(1.0, (x - edge0) / (edge1 - edge0)))
    return t * t * (3.0 - 2.0 * t)


class Lcg:
    """Numerical Recipes' 32-bit linear congruential generator: the same numbers everywhere."""

    def __init__(self, seed: int):
        self.state = seed & 0xFFFFFFFF

    def uniform(self, lo: float, hi: float) -> float:
        self.state = (1664525 * self.state + 1013904223) & 0xFFFFFFFF
        return lo + (hi - lo) * (self.state / 2**32)


def spot_coverage() -> list:
    """Per texel, in [0, 1]: how much of a spot covers it (1 inside, 0 on the background)."""
    rng = Lcg(20220427)
    cover = [[0.0] * SIZE for _ in range(SIZE)]
    for _ in range(40):
        cx, cy = rng.uniform(0, SIZE), rng.uniform(0, SIZE)
        radius = rng.uniform(6.0, 18.0)
        edge = rng.uniform(4.0, 8.0)
        outer = radius + edge / 2
        for dy in range(-math.ceil(outer) - 1, math.ceil(outer) + 2):
            y = (math.floor(cy) + dy) % SIZE
            for dx in range(-math.ceil(outer) - 1, math.ceil(outer) + 2):
                x = (math.floor(cx) + dx) % SIZE
                # Distance from the texel centre to the spot centre, wrapped (tileable).
                ddx = (x + 0.5 - cx + SIZE / 2) % SIZE - SIZE / 2
                ddy = (y + 0.5 - cy + SIZE / 2) % SIZE - SIZE / 2
                d = math.hypot(ddx, ddy)
                s = 1.0 - smoothstep(radius - edge / 2, radius + edge / 2, d)
                if s > cover[y][x]:
                    cover[y][x] = s
    return cover


def fabric() -> tuple:
    """Per texel: the check (0 smooth band, 1 rough band, smooth between) and the weave in [0, 1]."""
    check = [[0.0] * SIZE for _ in range(SIZE)]
    weave = [[0.0] * SIZE for _ in range(SIZE)]
    band = 64  # check period in texels; divides SIZE, so the pattern tiles
    thread = 8  # weave period in texels; divides SIZE
    for y in range(SIZE):
        sy = smoothstep(-0.35, 0.35, math.sin(2 * math.pi * (y + 0.5) / band))
        wy = math.cos(2 * math.pi * (y + 0.5) / thread)
        for x in range(SIZE):
            sx = smoothstep(-0.35, 0.35, math.sin(2 * math.pi * (x + 0.5) / band))
            check[y][x] = sx + sy - 2 * sx * sy  # a smooth exclusive or of the two stripe sets
            weave[y][x] = 0.5 + 0.5 * math.cos(2 * math.pi * (x + 0.5) / thread) * wy
    return check, weave


def mix(a: tuple, b: tuple, t: float) -> tuple:
    return tuple(p + (q - p) * t for p, q in zip(a, b))


def grey_rows(values: list) -> list:
    return [[to_byte(v) for v in row] for row in values]


def rgb_rows(colours: list) -> list:
    return [[to_byte(c) for colour in row for c in colour] for row in colours]


def textures() -> dict:
    cover = spot_coverage()
    check, weave = fabric()
    skin, spot = (0.34, 0.48, 0.23), (0.78, 0.36, 0.63)
    warm, light = (0.56, 0.23, 0.19), (0.77, 0.63, 0.47)
    shininess = [[0.1 + 0.8 * c for c in row] for row in cover]
    spot_colours = [[mix(skin, spot, c) for c in row] for row in cover]
    texels = [list(zip(cr, wr)) for cr, wr in zip(check, weave)]
    roughness = [[0.25 + 0.5 * c + 0.12 * (w - 0.5) for c, w in row] for row in texels]
    cloth = [[tuple(v * (0.85 + 0.15 * w) for v in mix(warm, light, c)) for c, w in row] for row in texels]
    return {
        "spots_shininess.png": png(SIZE, SIZE, 1, grey_rows(shininess)),
        "spots_albedo.png": png(SIZE, SIZE, 3, rgb_rows(spot_colours)),
        "fabric_roughness.png": png(SIZE, SIZE, 1, grey_rows(roughness)),
        "fabric_albedo.png": png(SIZE, SIZE, 3, rgb_rows(cloth)),
        "checker_8.png": png(8, 8, 1, [[255 * ((x + y) % 2) for x in range(8)] for y in range(8)]),
        "one_texel.png": png(1, 1, 1, [[200]]),
    }


def main() -> None:
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    for name, data in textures().items():
        (out / name).write_bytes(data)
        print(f"{out / name}: {len(data)} bytes")


if __name__ == "__main__":
    main()
