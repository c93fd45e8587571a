#!/usr/bin/env python3
"""Loop-subdivides a triangle mesh (Wavefront OBJ) STEPS times and writes the result as OBJ.

Charles Loop's scheme (1987): every triangle becomes four; a new vertex on an interior edge
(a, b) with opposite vertices c, d is 3/8 (a + b) + 1/8 (c + d), an old interior vertex with n
neighbours moves to (1 - n w) v + w * sum(neighbours) with
w = (5/8 - (3/8 + cos(2 pi / n) / 4)^2) / n. Edges with one face (the mesh boundary) or more
than two (non-manifold) are creases: their new vertex is the midpoint, and an old vertex on two
crease edges moves to 3/4 v + 1/8 (b0 + b1); one on other than two stays where it is.

Only `v` and triangular `f` lines are read (texture coordinates and normals are dropped: the
renderer computes smooth normals). Equal positions are welded first, so seams where a file
repeats its vertices (the teapot's patches) are subdivided smoothly instead of as creases.
Standard library only; the output is deterministic.

Usage:
    python3 scenes/tools/loop_subdivide.py INPUT.obj STEPS OUTPUT.obj
    python3 scenes/tools/loop_subdivide.py scenes/bunny.obj 1 scenes/bunny_dense.obj
    python3 scenes/tools/loop_subdivide.py scenes/teapot.obj 2 scenes/teapot_dense.obj
"""

import math
import sys


def read_obj(path):
    positions, faces = [], []
    with open(path, encoding="utf-8") as f:
        for line in f:
            words = line.split()
            if not words:
                continue
            if words[0] == "v":
                positions.append(tuple(float(w) for w in words[1:4]))
            elif words[0] == "f":
                corners = [int(w.split("/")[0]) for w in words[1:]]
                if len(corners) != 3:
                    raise ValueError(f"{path}: only triangles are supported, found a {len(corners)}-gon")
                faces.append(tuple(c - 1 if c > 0 else len(positions) + c for c in corners))
    return positions, faces


def weld(positions, faces):
    """One vertex per distinct position; faces that collapse are dropped."""
    index, welded, remap = {}, [], []
    for p in positions:
        if p not in index:
            index[p] = len(welded)
            welded.append(p)
        remap.append(index[p])
    out = []
    for a, b, c in faces:
        a, b, c = remap[a], remap[b], remap[c]
        if a != b and b != c and c != a:
            out.append((a, b, c))
    return welded, out


def add(p, q, s=1.0):
    return (p[0] + s * q[0], p[1] + s * q[1], p[2] + s * q[2])


def scale(p, s):
    return (p[0] * s, p[1] * s, p[2] * s)


def subdivide(positions, faces):
    # Each undirected edge: the vertices opposite it, one per face.
    opposite = {}
    for a, b, c in faces:
        for u, v, w in ((a, b, c), (b, c, a), (c, a, b)):
            opposite.setdefault((min(u, v), max(u, v)), []).append(w)
    neighbours = [set() for _ in positions]
    creases = [[] for _ in positions]
    for (u, v), across in opposite.items():
        neighbours[u].add(v)
        neighbours[v].add(u)
        if len(across) != 2:
            creases[u].append(v)
            creases[v].append(u)

    new_positions = []
    for i, p in enumerate(positions):
        n = len(neighbours[i])
        if creases[i]:
            if len(creases[i]) == 2:
                b0, b1 = (positions[j] for j in creases[i])
                new_positions.append(add(scale(p, 0.75), add(b0, b1), 0.125))
            else:
                new_positions.append(p)
        else:
            w = (5.0 / 8.0 - (3.0 / 8.0 + math.cos(2.0 * math.pi / n) / 4.0) ** 2) / n
            total = (0.0, 0.0, 0.0)
            for j in sorted(neighbours[i]):
                total = add(total, positions[j])
            new_positions.append(add(scale(p, 1.0 - n * w), total, w))

    edge_vertex = {}
    for (u, v) in sorted(opposite):
        across = opposite[(u, v)]
        mid = add(positions[u], positions[v])
        if len(across) == 2:
            q = add(scale(mid, 3.0 / 8.0), add(positions[across[0]], positions[across[1]]), 1.0 / 8.0)
        else:
            q = scale(mid, 0.5)
        edge_vertex[(u, v)] = len(new_positions)
        new_positions.append(q)

    def mid(u, v):
        return edge_vertex[(min(u, v), max(u, v))]

    new_faces = []
    for a, b, c in faces:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        new_faces += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return new_positions, new_faces


def main(argv):
    if len(argv) != 4:
        sys.exit(__doc__)
    source, steps, output = argv[1], int(argv[2]), argv[3]
    positions, faces = read_obj(source)
    before = (len(positions), len(faces))
    positions, faces = weld(positions, faces)
    for _ in range(steps):
        positions, faces = subdivide(positions, faces)
    name = source.replace("\\", "/").split("/")[-1]
    lines = [
        f"# {name} ({before[0]} vertices, {before[1]} triangles), equal positions welded, then {steps}",
        f"# Loop subdivision step(s): {len(positions)} vertices, {len(faces)} triangles.",
        f"# Generated by scenes/tools/loop_subdivide.py {name} {steps}.",
    ]
    lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in positions]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    with open(output, "w", encoding="utf-8", newline="\n") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(sys.argv)
