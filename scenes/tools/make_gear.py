#!/usr/bin/env python3
"""Writes a machined spur gear, a crease-heavy CAD-like part, as a Wavefront OBJ file.

The gear has 40 involute teeth (module 0.238, pressure angle 20 degrees, tip diameter 10, the
root on the base circle), a rim 2 thick whose outer tooth edges are chamfered at 45 degrees, a
recessed web 0.7 thick, a raised hub 2.6 thick and a bore of diameter 2 with a keyway; its axis
is Z and it is centred at the origin. It is built as one cross-section (in the r-z half-plane:
tooth wall, chamfer, rim face, rim step, web face, hub wall, hub face, bore, and back along the
bottom) swept around the axis through the samples of the tooth profile, so the mesh is one closed
surface (of genus 1) whose triangles all wind counter-clockwise seen from outside. The side walls
are cut into slices along Z and the faces into rings, as dense as a tessellated CAD export
(19,392 triangles, 9,696 vertices). The keyway is turned (within one tooth pitch of +Y) so that
its corners fall between the profile's samples, and samples are inserted there.

Every face corner has its own normal (`f v//vn`), so the creases stay sharp: flat faces (the
faces, the chamfers, the keyway's walls) carry their face normal; the bore, the hub and the rim
step, which are cylinders, carry radial normals, and so do the arcs of the tooth tips and roots;
the involute flanks carry the normal of the involute. Coordinates have at most 5 decimals.
Standard library only; the output is deterministic.

Usage:
    python3 scenes/tools/make_gear.py OUTPUT.obj
    python3 scenes/tools/make_gear.py scenes/gear.obj
"""

import math
import sys

TEETH = 40
PRESSURE_ANGLE = math.radians(20.0)
TIP_RADIUS = 5.0
MODULE = 2 * TIP_RADIUS / (TEETH + 2)
PITCH_RADIUS = MODULE * TEETH / 2
BASE_RADIUS = PITCH_RADIUS * math.cos(PRESSURE_ANGLE)  # the root circle, too

RIM_HALF = 1.0  # the rim and the teeth: z in [-1, 1]
CHAMFER = 0.05  # 45 degrees on the outer tooth edges
RIM_INNER = 3.7  # where the rim steps down to the web
WEB_HALF = 0.35
HUB_RADIUS = 1.9
HUB_HALF = 1.3
BORE_RADIUS = 1.0
KEY_WIDTH = 0.5
KEY_TOP = 1.3  # distance of the keyway's floor from the axis

FLANK_EDGES, TIP_EDGES, ROOT_EDGES = 3, 2, 2  # profile edges per flank, tip arc, root arc
WALL_SLICES, BORE_SLICES = 4, 4


def involute(alpha):
    return math.tan(alpha) - alpha


def inverse_involute(value):
    """The alpha in [0, pi/2) with tan(alpha) - alpha = value (Newton's method from alpha^3/3)."""
    alpha = (3 * value) ** (1 / 3)
    for _ in range(50):
        if alpha == 0:
            break
        alpha -= (involute(alpha) - value) / math.tan(alpha) ** 2
    return alpha


def flank_half_angle(r):
    """Angle between a tooth's centre line and its flank at radius r (standard tooth thickness
    of half the circular pitch on the pitch circle)."""
    alpha = math.acos(min(1.0, BASE_RADIUS / r))
    return math.pi / (2 * TEETH) + involute(PRESSURE_ANGLE) - involute(alpha)


def polar(r, angle):
    return (r * math.cos(angle), r * math.sin(angle))


def normalise(v):
    length = math.sqrt(sum(c * c for c in v))
    return tuple(c / length for c in v)


def outer_profile():
    """The tooth profile counter-clockwise, as (polar angle, radius, kind, None, curve) per
    sample: curve is the curve (arc, lead or trail flank) of the edge from the sample to the
    next, kind the same except for samples inserted on an edge later ("inserted")."""
    samples = []
    # Flank samples evenly spaced in polar angle (the involute leaves the base circle radially,
    # so samples evenly spaced along it would bunch up in angle, and the faces inside would be
    # needles): inv(alpha) runs evenly from 0 at the base circle to inv(alpha_tip).
    inv_tip = involute(math.acos(BASE_RADIUS / TIP_RADIUS))
    flank_radii = [BASE_RADIUS / math.cos(inverse_involute(inv_tip * i / FLANK_EDGES)) for i in range(FLANK_EDGES + 1)]
    for t in range(TEETH):
        centre = 2 * math.pi * t / TEETH
        # Leading flank, root to tip: angle centre - psi(r).
        for r in flank_radii[:-1]:
            samples.append((centre - flank_half_angle(r), r, "lead", None, "lead"))
        tip = flank_half_angle(TIP_RADIUS)
        for i in range(TIP_EDGES):
            samples.append((centre - tip + 2 * tip * i / TIP_EDGES, TIP_RADIUS, "arc", None, "arc"))
        for r in reversed(flank_radii[1:]):
            samples.append((centre + flank_half_angle(r), r, "trail", None, "trail"))
        start = centre + flank_half_angle(BASE_RADIUS)
        end = centre + 2 * math.pi / TEETH - flank_half_angle(BASE_RADIUS)
        for i in range(ROOT_EDGES):
            samples.append((start + (end - start) * i / ROOT_EDGES, BASE_RADIUS, "arc", None, "arc"))
    return samples


def flank_normal(angle, r, kind):
    """Outward normal of an involute flank at polar (angle, r), from the curve's tangent."""
    h = 1e-4
    sign = -1.0 if kind == "lead" else 1.0
    centre = angle - sign * flank_half_angle(r)
    r0, r1 = max(BASE_RADIUS, r - h), r + h
    a = polar(r0, centre + sign * flank_half_angle(r0))
    b = polar(r1, centre + sign * flank_half_angle(r1))
    tx, ty = b[0] - a[0], b[1] - a[1]
    if kind == "trail":  # travelled from tip to root: the tangent points inward
        tx, ty = -tx, -ty
    return normalise((ty, -tx))  # right of the counter-clockwise direction of travel


def key_axis_candidates():
    """Directions for the keyway: within one tooth pitch from +Y."""
    base = math.pi / 2
    return [base + 2 * math.pi / TEETH * i / 400 for i in range(400)]


def keyway_corners(axis):
    """Polar angles of the keyway's four corners for a slot along `axis`."""
    top = math.atan2(KEY_WIDTH / 2, KEY_TOP)
    side = math.asin(KEY_WIDTH / 2 / BORE_RADIUS)
    return [axis - side, axis - top, axis + top, axis + side]


def wrap(angle):
    return (angle + math.pi) % (2 * math.pi) - math.pi


def inner_point(angle, axis):
    """The bore with its keyway at polar angle `angle`: (point, piece), the piece being the
    circle, the keyway's floor or one of its walls (wall+ on the side of larger angles)."""
    d = wrap(angle - axis)
    top = math.atan2(KEY_WIDTH / 2, KEY_TOP)
    side = math.asin(KEY_WIDTH / 2 / BORE_RADIUS)
    if abs(d) <= top + 1e-12:
        return polar(KEY_TOP / math.cos(d), angle), "floor"
    if abs(d) <= side + 1e-12:
        return polar(KEY_WIDTH / 2 / abs(math.sin(d)), angle), ("wall+" if d > 0 else "wall-")
    return polar(BORE_RADIUS, angle), "circle"


def build():
    profile = outer_profile()
    angles = [s[0] for s in profile]

    # Place the keyway where its corners fall farthest from the profile's samples, and insert
    # samples at its corners, so that they are creases of the mesh.
    def gap(axis):
        return min(abs(wrap(c - a)) for c in keyway_corners(axis) for a in angles)

    axis = max(key_axis_candidates(), key=gap)
    for corner in keyway_corners(axis):
        c = corner % (2 * math.pi)
        for j in range(len(profile)):
            a0 = profile[j][0] % (2 * math.pi)
            a1 = profile[(j + 1) % len(profile)][0] % (2 * math.pi)
            inside = a0 < c < a1 if a0 < a1 else (c > a0 or c < a1)
            if inside:
                break
        else:
            raise AssertionError("corner outside the profile")
        # The point of the straight edge j -> j+1 at polar angle c (on the edge's curve).
        p0 = polar(profile[j][1], profile[j][0])
        p1 = polar(profile[(j + 1) % len(profile)][1], profile[(j + 1) % len(profile)][0])
        dx, dy = p1[0] - p0[0], p1[1] - p0[1]
        ux, uy = math.cos(c), math.sin(c)
        s = (p0[0] * uy - p0[1] * ux) / (dy * ux - dx * uy)
        x, y = p0[0] + s * dx, p0[1] + s * dy
        profile.insert(j + 1, (math.atan2(y, x), math.hypot(x, y), "inserted", s, profile[j][4]))
    n = len(profile)

    points = [polar(s[1], s[0]) for s in profile]

    def curve_normal(j, kind):
        """The outward normal at sample j of the curve `kind` (arc, lead or trail flank)."""
        if kind == "arc":
            return normalise(points[j])
        return flank_normal(profile[j][0], profile[j][1], kind)

    # Outward 2D normals per sample, one for each side: left[j] for the edge j-1 -> j, right[j]
    # for j -> j+1. They differ only at the corners, where the curve changes.
    left, right = [None] * n, [None] * n
    for j in range(n):
        if profile[j][2] != "inserted":
            right[j] = curve_normal(j, profile[j][4])
            left[j] = curve_normal(j, profile[j - 1][4])
    for j in range(n):
        if profile[j][2] == "inserted":  # on a chord: between its ends' normals
            a, b, t = right[j - 1], left[(j + 1) % n], profile[j][3]
            right[j] = left[j] = normalise(tuple(a[i] * (1 - t) + b[i] * t for i in range(2)))

    def edge_normal(j):
        a, b = points[j], points[(j + 1) % n]
        return normalise((b[1] - a[1], a[0] - b[0]))

    # The chamfer's inner edge: the profile offset inwards by CHAMFER, mitred at every sample,
    # so each chamfer quad lies between two parallel segments, at 45 degrees.
    offset = []
    for j in range(n):
        n1, n2 = edge_normal(j - 1), edge_normal(j)
        k = CHAMFER / (1 + n1[0] * n2[0] + n1[1] * n2[1])
        offset.append((points[j][0] - k * (n1[0] + n2[0]), points[j][1] - k * (n1[1] + n2[1])))

    # The rings inside the rim and the bore do not follow the profile's polar angles (the
    # involute starts almost radially, so two of its samples are only 0.09 degrees apart, which
    # would make needles of the faces): they are spaced evenly between the keyway's corners,
    # which keep their angles so that they stay creases.
    anchors = [j for j in range(n) if profile[j][2] == "inserted"]
    theta = [0.0] * n
    for i, a in enumerate(anchors):
        b = anchors[(i + 1) % len(anchors)]
        count = (b - a) % n
        start = math.atan2(points[a][1], points[a][0])
        span = (math.atan2(points[b][1], points[b][0]) - start) % (2 * math.pi)
        for step in range(count):
            theta[(a + step) % n] = start + span * step / count
    inner = [inner_point(a, axis) for a in theta]

    def inner_normals(j):
        """(left, right) normals of the bore at sample j."""
        prev_piece = piece_between(inner, theta, axis, j - 1)
        next_piece = piece_between(inner, theta, axis, j)
        return normal_of_piece(prev_piece, theta[j], axis), normal_of_piece(next_piece, theta[j], axis)

    ring = lambda r, j: polar(r, theta[j])

    def lerp(a, b, t):
        return (a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t)

    # The cross-section, bottom of the tooth wall first, then up the wall and inwards over the
    # top: (surface of the edge to the next point, function j -> (x, y), z).
    zc = RIM_HALF - CHAMFER
    section = []
    for i in range(1, WALL_SLICES):  # the wall's end points are the chamfers' (below)
        section.append(("wall", lambda j: points[j], -zc + 2 * zc * i / WALL_SLICES))
    top_half = [
        ("chamfer+", lambda j: points[j], zc),
        ("cap+", lambda j: offset[j], RIM_HALF),
        ("cap+", lambda j: lerp(offset[j], ring(RIM_INNER, j), 0.5), RIM_HALF),
        ("step", lambda j: ring(RIM_INNER, j), RIM_HALF),
        ("cap+", lambda j: ring(RIM_INNER, j), WEB_HALF),
        ("cap+", lambda j: ring((RIM_INNER + HUB_RADIUS) / 2, j), WEB_HALF),
        ("hub", lambda j: ring(HUB_RADIUS, j), WEB_HALF),
        ("cap+", lambda j: ring(HUB_RADIUS, j), HUB_HALF),
    ]
    section += top_half
    for i in range(BORE_SLICES):
        section.append(("bore", lambda j: inner[j][0], HUB_HALF - 2 * HUB_HALF * i / BORE_SLICES))
    section.append(("cap-", lambda j: inner[j][0], -HUB_HALF))
    # The bottom mirrors the top, walked the other way: each point takes the surface of the
    # edge that leaves it, which is the mirror of the edge arriving at its mirror image.
    mirrored = []
    surfaces = [s for s, _, _ in top_half]
    for i in reversed(range(len(top_half))):
        _, f, z = top_half[i]
        surface = surfaces[i - 1] if i > 0 else "wall"
        surface = {"chamfer+": "chamfer-", "cap+": "cap-"}.get(surface, surface)
        mirrored.append((surface, f, -z))
    section += mirrored
    m = len(section)

    positions = []
    for j in range(n):
        for surface, f, z in section:
            x, y = f(j)
            positions.append((x, y, z))

    def vid(j, k):
        return (j % n) * m + (k % m)

    def corner_normal(surface, j, side_is_right):
        if surface == "wall":
            nx, ny = right[j] if side_is_right else left[j]
            return (nx, ny, 0.0)
        if surface in ("chamfer+", "chamfer-"):
            nx, ny = right[j] if side_is_right else left[j]
            return normalise((nx, ny, 1.0 if surface == "chamfer+" else -1.0))
        if surface == "cap+":
            return (0.0, 0.0, 1.0)
        if surface == "cap-":
            return (0.0, 0.0, -1.0)
        if surface == "hub":
            return (math.cos(theta[j]), math.sin(theta[j]), 0.0)
        if surface == "step":
            return (-math.cos(theta[j]), -math.sin(theta[j]), 0.0)
        if surface == "bore":
            lft, rgt = inner_normals(j)
            nx, ny = rgt if side_is_right else lft
            return (nx, ny, 0.0)
        raise AssertionError(surface)

    triangles = []  # ((v, normal) x 3)
    for j in range(n):
        for k in range(m):
            surface = section[k][0]
            a, b, c, d = (j, k), (j + 1, k), (j + 1, k + 1), (j, k + 1)

            def corner(q):
                return vid(*q), corner_normal(surface, q[0] % n, q[0] == j)

            pa, pb, pc, pd = (positions[vid(*q)] for q in (a, b, c, d))
            if dist2(pa, pc) <= dist2(pb, pd):
                quads = [(a, b, c), (a, c, d)]
            else:
                quads = [(a, b, d), (b, c, d)]
            for tri in quads:
                triangles.append(tuple(corner(q) for q in tri))
    return positions, triangles, axis


def piece_between(inner, theta, axis, j):
    """The piece of the bore (circle, floor, wall+, wall-) that the edge j -> j+1 lies on."""
    n = len(theta)
    a0, a1 = theta[j % n], theta[(j + 1) % n]
    mid = a0 + wrap(a1 - a0) / 2
    return inner_point(mid, axis)[1]


def normal_of_piece(piece, angle, axis):
    """The normal of a piece of the bore, out of the solid (into the hole)."""
    ax, ay = math.cos(axis), math.sin(axis)
    if piece == "circle":
        return (-math.cos(angle), -math.sin(angle))
    if piece == "floor":
        return (-ax, -ay)
    if piece == "wall+":
        return (ay, -ax)
    return (-ay, ax)


def dist2(p, q):
    return sum((p[i] - q[i]) ** 2 for i in range(3))


def fmt(x):
    s = f"{x:.5f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def gear_obj():
    positions, triangles, axis = build()
    normal_index = {}
    normal_lines = []
    faces = []
    for tri in triangles:
        corners = []
        for v, normal in tri:
            key = " ".join(fmt(c) for c in normal)
            if key not in normal_index:
                normal_index[key] = len(normal_lines) + 1
                normal_lines.append(f"vn {key}")
            corners.append(f"{v + 1}//{normal_index[key]}")
        faces.append("f " + " ".join(corners))
    # Every triangle must face the way its corners' normals do.
    for tri in triangles:
        p = [positions[v] for v, _ in tri]
        u = [p[1][i] - p[0][i] for i in range(3)]
        w = [p[2][i] - p[0][i] for i in range(3)]
        g = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
        for _, normal in tri:
            assert sum(g[i] * normal[i] for i in range(3)) > 0, "triangle faces against its normals"
    lines = [
        f"# Spur gear: {TEETH} involute teeth (module {MODULE:.4f}, pressure angle 20 deg), tip diameter"
        f" {2 * TIP_RADIUS:g}, chamfered rim {2 * RIM_HALF:g} thick, web {2 * WEB_HALF:g}, hub"
        f" {2 * HUB_HALF:g}, keyed bore diameter {2 * BORE_RADIUS:g}; axis Z, centred at the origin.",
        f"# Generated by scenes/tools/make_gear.py; {len(positions)} vertices, {len(normal_lines)}"
        f" normals, {len(triangles)} triangles; closed, counter-clockwise seen from outside.",
        "o gear",
    ]
    lines += [f"v {fmt(x)} {fmt(y)} {fmt(z)}" for x, y, z in positions]
    lines += normal_lines
    lines += faces
    return "\n".join(lines) + "\n", len(positions), len(triangles)


def main() -> None:
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    output = sys.argv[1]
    text, vertices, triangles = gear_obj()
    with open(output, "w", encoding="ascii", newline="\n") as f:
        f.write(text)
    print(f"{output}: {vertices} vertices, {triangles} triangles")


if __name__ == "__main__":
    main()
