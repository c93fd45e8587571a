#!/usr/bin/env python3
"""Writes an organic, "sculpted" closed surface of about 110,000 triangles as a Wavefront OBJ.

The surface starts as a geodesic sphere: an icosahedron whose 20 faces are each cut into
FREQUENCY^2 triangles (FREQUENCY 74: 109,520 triangles, 54,762 vertices, every vertex shared,
no poles and so no fans of slivers), pushed out to the unit sphere. Each vertex is then moved
along its direction to the radius r(d) = 1 + a sum of smooth fields of the direction d: a waist,
a dozen broad lumps and dents, five spiralling flutes, a folded band, ridges and fine ripples,
and a flat base blended in smoothly. A surface r(d) of a positive r is star-shaped, so it stays
closed and does not cross itself; it is then stretched across Y, twisted about Y (a twist is a
one-to-one map of space, so it still does not cross itself), centred at the origin and scaled so
that it is 10 units tall (Y up).

Faces wind counter-clockwise seen from outside, as the icosahedron's do. Only positions and faces
are written (the loader computes smooth normals), with at most 5 decimals. Standard library
only; every number comes from fixed formulas, so the output is the same on every run.

Usage:
    python3 scenes/tools/make_sculpture.py OUTPUT.obj
    python3 scenes/tools/make_sculpture.py scenes/sculpture.obj
"""

import math
import sys

FREQUENCY = 74
HEIGHT = 10.0
BASE = -0.8  # the base plane, before stretching (the unit sphere reaches -1)


def icosahedron():
    t = (1 + math.sqrt(5)) / 2
    raw = [
        (-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0),
        (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
        (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1),
    ]
    faces = [
        (0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11),
        (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
        (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9),
        (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1),
    ]
    return [normalise(v) for v in raw], faces


def normalise(v):
    length = math.sqrt(sum(c * c for c in v))
    return tuple(c / length for c in v)


def geodesic_sphere(frequency):
    """Unit directions and triangles. A vertex is named by its integer barycentric weights on
    the icosahedron's vertices, so the vertices on an edge shared by two faces are shared."""
    corners, ico_faces = icosahedron()
    index = {}
    directions = []
    faces = []

    def vertex(weights):
        key = tuple(sorted((c, w) for c, w in weights if w > 0))
        if key not in index:
            p = [sum(corners[c][k] * w for c, w in key) / frequency for k in range(3)]
            index[key] = len(directions)
            directions.append(normalise(p))
        return index[key]

    for a, b, c in ico_faces:
        grid = {}
        for i in range(frequency + 1):
            for j in range(frequency + 1 - i):
                grid[i, j] = vertex(((a, frequency - i - j), (b, i), (c, j)))
        for i in range(frequency):
            for j in range(frequency - i):
                faces.append((grid[i, j], grid[i + 1, j], grid[i, j + 1]))
                if i + j + 1 < frequency:
                    faces.append((grid[i + 1, j], grid[i + 1, j + 1], grid[i, j + 1]))
    return directions, faces


def lump_centres(count):
    """Evenly spread directions (a Fibonacci spiral), for the lumps and dents."""
    golden = math.pi * (3 - math.sqrt(5))
    out = []
    for i in range(count):
        y = 1 - 2 * (i + 0.5) / count
        r = math.sqrt(1 - y * y)
        out.append((r * math.cos(golden * i), y, r * math.sin(golden * i)))
    return out


LUMPS = [
    # (centre, amplitude, width in radians): alternately lumps and dents of varied size.
    (c, (0.16 if i % 2 == 0 else -0.1) * (0.7 + 0.6 * ((i * 7) % 5) / 4), 0.28 + 0.2 * ((i * 3) % 4) / 3)
    for i, c in enumerate(lump_centres(12))
]


def radius(d):
    x, y, z = d
    r = 1.0
    # A waist a little above the middle, and a broader base.
    r -= 0.3 * math.exp(-((y - 0.2) ** 2) / 0.05)
    r += 0.12 * math.exp(-((y + 0.5) ** 2) / 0.1)
    # Lumps and dents.
    for c, amplitude, width in LUMPS:
        r += amplitude * math.exp((x * c[0] + y * c[1] + z * c[2] - 1) / (width * width))
    # Five spiralling flutes: Re((x + iz)^5 e^(i 3 y)), a polynomial in x and z, so smooth at
    # the poles, where it fades out.
    rho2 = x * x + z * z
    phi = math.atan2(z, x)
    r += 0.13 * rho2 ** 2.5 * math.cos(5 * phi + 3 * y)
    # A folded band around a tilted axis: a sine whose phase is bent by another sine.
    u = 0.8 * x + 0.6 * y
    v = -0.48 * x + 0.64 * y + 0.6 * z
    band = math.exp(-((0.6 * x - 0.8 * z + 0.1) ** 2) / 0.18)
    r += 0.08 * band * math.sin(9 * u + 1.6 * math.sin(4 * v))
    # Ridges with rounded crests (1 - sqrt(sin^2 + e)) on the upper part.
    s = math.sin(6 * (0.3 * x + 0.95 * y - 0.1 * z) + 0.7)
    r += 0.07 * (1 - math.sqrt(s * s + 0.04)) * max(0.0, y + 0.2) ** 2
    # Fine ripples, like tool marks.
    r += 0.015 * math.sin(23 * (0.57 * x + 0.23 * y + 0.79 * z)) * math.sin(19 * (-0.7 * x + 0.7 * y + 0.14 * z))
    # A flat base to stand on: the plane y = BASE cuts the bottom, blended in smoothly (a soft
    # minimum of r and the plane's radius along d).
    if y < -0.2:
        plane = BASE / y
        k = 0.025
        r = -k * math.log(math.exp(-r / k) + math.exp(-plane / k))
    return r


def sculpture(frequency):
    directions, faces = geodesic_sphere(frequency)
    positions = []
    for d in directions:
        r = radius(d)
        assert r > 0.3, "the surface must stay star-shaped"
        x, y, z = (c * r for c in d)
        x, y, z = 0.72 * x, y, 0.62 * z  # narrower across Y than along it
        angle = 0.55 * y  # twisted about Y
        c, s = math.cos(angle), math.sin(angle)
        positions.append((c * x + s * z, y, -s * x + c * z))
    lo = [min(p[k] for p in positions) for k in range(3)]
    hi = [max(p[k] for p in positions) for k in range(3)]
    centre = [(lo[k] + hi[k]) / 2 for k in range(3)]
    scale = HEIGHT / (hi[1] - lo[1])
    positions = [tuple((p[k] - centre[k]) * scale for k in range(3)) for p in positions]
    return positions, faces


def fmt(x):
    s = f"{x:.5f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def main() -> None:
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    output = sys.argv[1]
    positions, faces = sculpture(FREQUENCY)
    lines = [
        f"# Sculpted closed surface: a geodesic sphere (frequency {FREQUENCY}) displaced by smooth fields,"
        f" stretched, twisted, {HEIGHT:g} units tall (Y up), centred at the origin.",
        f"# Generated by scenes/tools/make_sculpture.py; {len(positions)} vertices, {len(faces)} triangles;"
        " closed, counter-clockwise seen from outside.",
        "o sculpture",
    ]
    lines += [f"v {fmt(x)} {fmt(y)} {fmt(z)}" for x, y, z in positions]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    with open(output, "w", encoding="ascii", newline="\n") as f:
        f.write("\n".join(lines) + "\n")
    print(f"{output}: {len(positions)} vertices, {len(faces)} triangles")


if __name__ == "__main__":
    main()
