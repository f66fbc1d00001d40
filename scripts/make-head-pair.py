#!/usr/bin/env python3
"""make-head-pair.py — writes the small head mesh and strand groom under assets/.

  scripts/make-head-pair.py            # assets/meshes/head.obj, assets/grooms/head_bob.hair

Both are made the way a downloaded pair often comes: in centimetres with +z up (the scene
turns them into clhair's metres and +y up with "scale": 0.01, "up": "z"), the face toward
-y. The head is a radial function of the direction d from its centre: the ellipsoid's
radius along d, narrowed toward the jaw, plus Gaussian bumps for the nose, the chin and
the brow, sampled on a latitude/longitude grid (1490 vertices, 2976 triangles). The groom
is 1200 strands of 10 points rooted on the scalp (a Fibonacci set of directions, the face
left out) that leave along the surface normal, bend down under gravity (swept back and
parted in front of the face) and are pushed out of the head wherever a step would enter it. Deterministic: no random numbers.
"""
import math
import os
import struct

RADII = (7.6, 9.4, 11.0)  # x (ear to ear), y (back to front), z (up), cm
BUMPS = [  # direction, amplitude (cm), angular width (radians)
    ((0.0, -1.0, -0.05), 1.6, 0.16),  # nose
    ((0.0, -0.75, -0.66), 0.9, 0.30),  # chin
    ((0.0, -0.93, 0.37), 0.35, 0.45),  # brow
]
RINGS, SEGMENTS = 32, 48
STRANDS, POINTS = 1200, 10

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "assets")


def norm(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


def radius(d):
    """Distance from the centre to the head's surface along unit direction d."""
    x, y, z = d
    r = 1.0 / math.sqrt((x / RADII[0]) ** 2 + (y / RADII[1]) ** 2 + (z / RADII[2]) ** 2)
    if z < -0.2:  # the jaw: narrower toward the chin
        t = min(1.0, (-0.2 - z) / 0.7)
        r *= 1.0 - 0.18 * t * t * (1.0 - abs(y))
    for bd, amp, width in BUMPS:
        b = norm(bd)
        ang = math.acos(max(-1.0, min(1.0, x * b[0] + y * b[1] + z * b[2])))
        r += amp * math.exp(-((ang / width) ** 2))
    return r


def surface(d):
    r = radius(d)
    return (d[0] * r, d[1] * r, d[2] * r)


def fmt(v):
    return " ".join("%.4g" % c for c in v)


def write_head(path):
    verts = [surface((0.0, 0.0, 1.0))]
    for i in range(1, RINGS):
        th = math.pi * i / RINGS
        for j in range(SEGMENTS):
            ph = 2.0 * math.pi * j / SEGMENTS
            verts.append(surface((math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th))))
    verts.append(surface((0.0, 0.0, -1.0)))
    bottom = len(verts)  # 1-based index of the last vertex

    def ring(i, j):  # 1-based index of ring i (1..RINGS-1), segment j
        return 2 + (i - 1) * SEGMENTS + j % SEGMENTS

    faces = []
    for j in range(SEGMENTS):
        faces.append((1, ring(1, j), ring(1, j + 1)))
        faces.append((bottom, ring(RINGS - 1, j + 1), ring(RINGS - 1, j)))
    for i in range(1, RINGS - 1):
        for j in range(SEGMENTS):
            a, b, c, d = ring(i, j), ring(i, j + 1), ring(i + 1, j + 1), ring(i + 1, j)
            faces.append((a, d, c))
            faces.append((a, c, b))
    with open(path, "w") as f:
        f.write("# clhair example head: centimetres, +z up, face toward -y (scripts/make-head-pair.py)\n")
        f.write("o head\n")
        for v in verts:
            f.write("v %s\n" % fmt(v))
        for t in faces:
            f.write("f %d %d %d\n" % t)
    return len(verts), len(faces)


def write_groom(path):
    points = []
    golden = math.pi * (3.0 - math.sqrt(5.0))
    kept = 0
    k = 0
    while kept < STRANDS:
        # Fibonacci directions over the upper part of the sphere
        z = 1.0 - 1.3 * (k + 0.5) / (STRANDS * 1.9)
        k += 1
        rxy = math.sqrt(max(0.0, 1.0 - z * z))
        d = (rxy * math.cos(golden * k), rxy * math.sin(golden * k), z)
        if d[1] < -0.25 and d[2] < 0.62:  # the face and forehead
            continue
        if d[2] < 0.05 and d[1] < 0.3:  # below the temples, except the back of the head
            continue
        kept += 1
        length = 17.0 + 5.0 * math.sin(7.0 * k)  # cm
        step = length / (POINTS - 1)
        p = surface(d)
        direction = d
        strand = [p]
        # roots toward the face are swept back (+y) and to their side, parted at the middle
        front = max(0.0, -d[1])
        side = math.copysign(0.25 * front, d[0] if d[0] != 0.0 else 1.0)
        for _ in range(POINTS - 1):
            direction = norm((0.6 * direction[0] + side, 0.6 * direction[1] + 0.08 + 0.5 * front,
                              0.6 * direction[2] - 0.45))
            q = tuple(p[c] + step * direction[c] for c in range(3))
            n = math.sqrt(sum(c * c for c in q))
            r = radius(tuple(c / n for c in q)) * 1.04 + 0.15
            if n < r:  # inside the head (with a margin): onto the surface
                q = tuple(c * r / n for c in q)
            strand.append(q)
            p = q
        points.extend(strand)
    header = struct.pack("<4sIIIIff3f", b"HAIR", STRANDS, STRANDS * POINTS, 2, POINTS - 1, 0.008, 0.0, 0.3, 0.2, 0.1)
    info = b"clhair example groom: cm, +z up".ljust(88, b"\0")
    with open(path, "wb") as f:
        f.write(header + info)
        for q in points:
            f.write(struct.pack("<3f", *q))
    return len(points)


if __name__ == "__main__":
    v, t = write_head(os.path.join(ROOT, "meshes", "head.obj"))
    print("assets/meshes/head.obj: %d vertices, %d triangles" % (v, t))
    n = write_groom(os.path.join(ROOT, "grooms", "head_bob.hair"))
    print("assets/grooms/head_bob.hair: %d strands, %d points" % (STRANDS, n))
