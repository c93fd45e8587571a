#!/usr/bin/env python3
"""Writes a small vaulted chapel, a textured multi-material interior: an OBJ file, its MTL
library and two textures.

The hall is 10 wide (X, -5 to 5), 24 long (Z, -12 to 12) and 6 high to the springing of a
barrel vault of radius 5 (its crown at Y = 11); Y is up and the floor is at Y = 0. Two rows of
four round columns (16 sides, on square bases, under square capitals) carry a beam along each
side of the nave; a gilded altar stands before the far end wall (Z = -12), under a window pane
set into the wall's lunette. Every surface faces into the hall and every corner has its normal
(`vn`) and texture coordinates (`vt`).

Materials (chapel.mtl), six, of every BRDF kind the renderer has:

- floor_marble   Lambert, `map_Kd textures/chapel_floor.png`: marble tiles, the texture
                 repeating every 1.25 (u = x / 1.25, v = z / 1.25: from -4 to 4 across the
                 floor and -9.6 to 9.6 along it, far outside [0, 1]);
- stone_wall     Lambert, `map_Kd textures/chapel_stone.png`: ashlar blocks, repeating every
                 2 along the wall and 1.5 up it;
- vault_plaster  Lambert;
- column_stone   Blinn-Phong (Ks, Ns);
- altar_gold     GGX (Pr, Pm: metallic);
- window_glass   Blinn-Phong, with a transparency (`d 0.45`) that the renderer does not model.

The library also has statements the renderer does not model (`map_Ka`, `map_Bump`, `d` below
1), so that loading it shows their warnings, each once.

Textures (RGB, 128 x 128, tileable): chapel_floor.png, two-by-two tiles of cream and grey
marble with veins and grout; chapel_stone.png, four courses of staggered blocks in varied tints
with mortar joints. Standard library only (the PNG writer is make_textures.py's); every run
writes the same bytes.

Usage:
    python3 scenes/tools/make_chapel.py OUTPUT_FOLDER
    python3 scenes/tools/make_chapel.py scenes
(writes OUTPUT_FOLDER/chapel.obj, chapel.mtl and textures/chapel_floor.png, chapel_stone.png)
"""

import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from make_textures import Lcg, mix, png, rgb_rows, smoothstep  # noqa: E402

TEXTURE_SIZE = 128
HALF_WIDTH = 5.0
HALF_LENGTH = 12.0
WALL_HEIGHT = 6.0
VAULT_SEGMENTS = 16
COLUMN_SIDES = 16
COLUMN_X = 3.0
COLUMN_Z = (-7.5, -2.5, 2.5, 7.5)


def sub(a, b):
    return tuple(p - q for p, q in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(p * q for p, q in zip(a, b))


def normalize(a):
    length = math.sqrt(dot(a, a))
    return tuple(c / length for c in a)


class Obj:
    """Vertices, texture coordinates, normals and, per material, faces of corner index triples."""

    def __init__(self):
        self.positions, self.uvs, self.normals = [], [], []
        self.known = {}
        self.faces = {}

    def index(self, table, value):
        """The 1-based index of `value` (rounded as written) in `table`, added where it is new."""
        key = (id(table), tuple(f"{c:.5f}" for c in value))
        if key not in self.known:
            table.append(value)
            self.known[key] = len(table)
        return self.known[key]

    def triangle(self, material, corners):
        """corners: three (position, uv, normal); wound so that its face normal agrees with the
        corners' normals; dropped where it has no area."""
        p = [c[0] for c in corners]
        face = cross(sub(p[1], p[0]), sub(p[2], p[0]))
        if dot(face, face) < 1e-12:
            return
        if dot(face, corners[0][2]) < 0:
            corners = [corners[0], corners[2], corners[1]]
        triple = [
            (self.index(self.positions, c[0]), self.index(self.uvs, c[1]), self.index(self.normals, c[2]))
            for c in corners
        ]
        self.faces.setdefault(material, []).append(triple)

    def grid(self, material, point, normal, uv, nu, nv):
        """A surface point(s, t), s and t in [0, 1], cut into nu x nv quads (two triangles each)."""
        corner = lambda i, j: (point(i / nu, j / nv), uv(point(i / nu, j / nv)), normal(i / nu, j / nv))
        for j in range(nv):
            for i in range(nu):
                a, b, c, d = corner(i, j), corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1)
                self.triangle(material, [a, b, c])
                self.triangle(material, [a, c, d])

    def quad(self, material, origin, u, v, normal, uv, nu=1, nv=1):
        """The parallelogram origin + s·u + t·v, facing `normal`."""
        point = lambda s, t: tuple(o + s * p + t * q for o, p, q in zip(origin, u, v))
        self.grid(material, point, lambda s, t: normal, uv, nu, nv)

    def box(self, material, lo, hi, uv, faces="xXyYzZ"):
        """An axis-aligned box facing outwards; `faces` picks its sides (x: -X, X: +X, ...)."""
        (x0, y0, z0), (x1, y1, z1) = lo, hi
        sides = {
            "x": ((x0, y0, z0), (0, 0, z1 - z0), (0, y1 - y0, 0), (-1, 0, 0)),
            "X": ((x1, y0, z0), (0, 0, z1 - z0), (0, y1 - y0, 0), (1, 0, 0)),
            "y": ((x0, y0, z0), (x1 - x0, 0, 0), (0, 0, z1 - z0), (0, -1, 0)),
            "Y": ((x0, y1, z0), (x1 - x0, 0, 0), (0, 0, z1 - z0), (0, 1, 0)),
            "z": ((x0, y0, z0), (x1 - x0, 0, 0), (0, y1 - y0, 0), (0, 0, -1)),
            "Z": ((x0, y0, z1), (x1 - x0, 0, 0), (0, y1 - y0, 0), (0, 0, 1)),
        }
        for side in faces:
            origin, u, v, normal = sides[side]
            self.quad(material, origin, u, v, normal, uv)

    def text(self, library):
        lines = [
            "# A small vaulted chapel: written by scenes/tools/make_chapel.py (do not edit).",
            f"# {len(self.positions)} positions, {sum(len(f) for f in self.faces.values())} triangles, "
            f"{len(self.faces)} materials.",
            f"mtllib {library}",
        ]
        lines += [f"v {x:.5f} {y:.5f} {z:.5f}" for x, y, z in self.positions]
        lines += [f"vt {u:.5f} {v:.5f}" for u, v in self.uvs]
        lines += [f"vn {x:.5f} {y:.5f} {z:.5f}" for x, y, z in self.normals]
        for material, faces in self.faces.items():
            lines += [f"o {material}", f"usemtl {material}"]
            lines += ["f " + " ".join(f"{p}/{t}/{n}" for p, t, n in face) for face in faces]
        return "\n".join(lines) + "\n"


def chapel() -> Obj:
    obj = Obj()
    w, h, length = HALF_WIDTH, WALL_HEIGHT, HALF_LENGTH
    floor_uv = lambda p: (p[0] / 1.25, p[2] / 1.25)
    obj.quad("floor_marble", (-w, 0, -length), (2 * w, 0, 0), (0, 0, 2 * length), (0, 1, 0), floor_uv, 8, 16)

    # Side walls (u along Z), end walls (u along X): blocks 2 long and 1.5 high.
    along_z = lambda p: (p[2] / 2.0, p[1] / 1.5)
    along_x = lambda p: (p[0] / 2.0, p[1] / 1.5)
    obj.quad("stone_wall", (-w, 0, -length), (0, 0, 2 * length), (0, h, 0), (1, 0, 0), along_z, 12, 3)
    obj.quad("stone_wall", (w, 0, -length), (0, 0, 2 * length), (0, h, 0), (-1, 0, 0), along_z, 12, 3)
    for z, normal in ((-length, (0, 0, 1)), (length, (0, 0, -1))):
        obj.quad("stone_wall", (-w, 0, z), (2 * w, 0, 0), (0, h, 0), normal, along_x, 5, 3)
        # The lunette under the vault: a half disc in polar cells.
        lunette = lambda s, t, z=z: (w * s * math.cos(math.pi * t), h + w * s * math.sin(math.pi * t), z)
        obj.grid("stone_wall", lunette, lambda s, t, n=normal: n, along_x, 4, VAULT_SEGMENTS)

    # The barrel vault, its normals towards its axis.
    vault = lambda s, t: (w * math.cos(math.pi * t), h + w * math.sin(math.pi * t), -length + 2 * length * s)
    inwards = lambda s, t: (-math.cos(math.pi * t), -math.sin(math.pi * t), 0.0)
    obj.grid("vault_plaster", vault, inwards, lambda p: (p[2] / 3.0, p[0] / 3.0), 12, VAULT_SEGMENTS)

    # Columns: a base, a round shaft, a capital; a beam along each row.
    plain = lambda p: (p[0] + p[2], p[1])
    radius = 0.35
    for x in (-COLUMN_X, COLUMN_X):
        for z in COLUMN_Z:
            obj.box("column_stone", (x - 0.45, 0.0, z - 0.45), (x + 0.45, 0.3, z + 0.45), plain, "xXYzZ")
            shaft = lambda s, t, x=x, z=z: (
                x + radius * math.cos(2 * math.pi * s),
                0.3 + 5.3 * t,
                z - radius * math.sin(2 * math.pi * s),
            )
            outwards = lambda s, t: (math.cos(2 * math.pi * s), 0.0, -math.sin(2 * math.pi * s))
            obj.grid("column_stone", shaft, outwards, plain, COLUMN_SIDES, 4)
            obj.box("column_stone", (x - 0.5, 5.6, z - 0.5), (x + 0.5, 6.0, z + 0.5), plain, "xXyzZ")
        obj.box("column_stone", (x - 0.4, 6.0, -9.0), (x + 0.4, 6.6, 9.0), plain, "xXyYzZ")

    # The altar on its step, and the window pane a little in front of the far wall's lunette.
    obj.box("vault_plaster", (-2.0, 0.0, -11.0), (2.0, 0.2, -8.8), plain, "xXYZ")
    obj.box("altar_gold", (-1.2, 0.2, -10.5), (1.2, 1.2, -9.5), plain, "xXYZ")
    obj.quad("window_glass", (-1.2, 7.0, -length + 0.02), (2.4, 0, 0), (0, 2.6, 0), (0, 0, 1), along_x)
    return obj


LIBRARY = """\
# The chapel's materials: written by scenes/tools/make_chapel.py (do not edit).
# map_Ka, map_Bump and d below 1 are here on purpose: the renderer does not model them and says so.

newmtl floor_marble
Ka 1.000 1.000 1.000
Kd 0.850 0.850 0.850
Ks 0.000 0.000 0.000
d 1.0
illum 1
map_Kd textures/chapel_floor.png
map_Ka textures/chapel_floor.png

newmtl stone_wall
Ka 1.000 1.000 1.000
Kd 0.800 0.780 0.740
Ks 0.000 0.000 0.000
Tr 0.0
illum 1
map_Kd textures/chapel_stone.png
map_Ka textures/chapel_stone.png
map_Bump -bm 0.4 textures/chapel_stone.png

newmtl vault_plaster
Kd 0.620 0.580 0.520

newmtl column_stone
Kd 0.560 0.520 0.470
Ks 0.300 0.300 0.300
Ns 48

newmtl altar_gold
Kd 1.000 0.780 0.340
Pr 0.35
Pm 1.0

newmtl window_glass
Kd 0.300 0.450 0.800
Ks 0.600 0.600 0.600
Ns 120
Ni 1.5
d 0.45
illum 4
"""


def floor_texture() -> list:
    """Two-by-two marble tiles (cream and grey) with soft veins, between grout lines."""
    n, half = TEXTURE_SIZE, TEXTURE_SIZE // 2
    cream, grey, grout = (0.86, 0.82, 0.72), (0.42, 0.43, 0.46), (0.3, 0.28, 0.25)
    rows = []
    for y in range(n):
        row = []
        for x in range(n):
            base = cream if (x // half + y // half) % 2 == 0 else grey
            vein = 0.5 + 0.5 * math.sin(2 * math.pi * (x + 0.6 * y) / half + 3 * math.sin(2 * math.pi * y / half))
            colour = mix(base, tuple(0.75 * c for c in base), smoothstep(0.85, 1.0, vein))
            # Grout: within 1.5 texels of a tile edge.
            edge = min(min(x % half, half - 1 - x % half), min(y % half, half - 1 - y % half))
            row.append(mix(grout, colour, smoothstep(0.5, 2.0, edge)))
        rows.append(row)
    return rows


def stone_texture() -> list:
    """Four courses of blocks, each course shifted by half a block, each block its own tint."""
    n, course, block = TEXTURE_SIZE, TEXTURE_SIZE // 4, TEXTURE_SIZE // 2
    rng = Lcg(20240611)
    tints = [[rng.uniform(0.8, 1.1) for _ in range(2)] for _ in range(4)]
    sand, mortar = (0.78, 0.7, 0.58), (0.55, 0.52, 0.48)
    rows = []
    for y in range(n):
        row = []
        c = y // course
        shift = (c % 2) * block // 2
        for x in range(n):
            b = ((x + shift) % n) // block
            colour = tuple(min(1.0, v * tints[c][b]) for v in sand)
            edge = min(y % course, course - 1 - y % course, (x + shift) % block, block - 1 - (x + shift) % block)
            row.append(mix(mortar, colour, smoothstep(0.5, 2.0, edge)))
        rows.append(row)
    return rows


def main() -> None:
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    (out / "textures").mkdir(parents=True, exist_ok=True)
    files = {
        "chapel.obj": chapel().text("chapel.mtl").encode(),
        "chapel.mtl": LIBRARY.encode(),
        "textures/chapel_floor.png": png(TEXTURE_SIZE, TEXTURE_SIZE, 3, rgb_rows(floor_texture())),
        "textures/chapel_stone.png": png(TEXTURE_SIZE, TEXTURE_SIZE, 3, rgb_rows(stone_texture())),
    }
    for name, data in files.items():
        (out / name).write_bytes(data)
        print(f"{out / name}: {len(data)} bytes")


if __name__ == "__main__":
    main()
