#!/usr/bin/env python3
"""make-outside-groom.py - a groom made by rules clhair's generator does not have.

Writes a cyHair .hair file (points only, default thickness 7e-5) of strands on a head-sized
sphere cap (radius 0.095, crown at +y, the face toward +z), for measuring `clhair fit-mesh`
on strands from outside the project (docs/fitting.md). Nothing here is clhair's hair-mesh
model: there are no bundles, no layers and no Hermite curves.

  - Roots: uniform random on the cap (rejection sampling), not blue noise.
  - Growth: each strand is integrated in small steps from its root, its direction blended
    from the scalp normal toward a combed direction (backward and outward) and pulled down
    by a gravity that grows with length; it is pushed out of the head sphere.
  - Curl: a spring whose radius grows linearly from root to tip (clhair's curl ramps in over
    the first 15 % and then keeps its amplitude), whose pitch varies by +-25 % from strand to
    strand (clhair: one frequency per groom), with a random phase per strand (clhair: a phase
    per clump) and a handedness drawn per strand (clhair's helices turn one way).
  - Noise: Gaussian steps of a random walk added to the direction (clhair: smooth value
    noise growing with w^2).
  - Lengths: normally distributed around a length that depends on the root's place
    (clhair: uniform shortening of the bundle's curve).
  - Points: 40 per strand, evenly spaced along the integration (clhair: 2^k + 1).

Usage: scripts/make-outside-groom.py OUT.hair [--strands N] [--seed S]
Pure Python (struct, math, random): no numpy needed.
"""

import argparse
import math
import random
import struct

HEAD_RADIUS = 0.095
POINTS = 40


def normalize(v):
    length = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    return (v[0] / length, v[1] / length, v[2] / length) if length > 0 else (0.0, 1.0, 0.0)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def random_root(rng):
    """A point on the cap: above the ears at the sides, lower at the back, a hairline in front."""
    while True:
        d = normalize((rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)))
        polar = math.degrees(math.acos(max(-1.0, min(1.0, d[1]))))
        azimuth = math.atan2(d[0], d[2])  # 0: the face
        limit = 95.0 - 25.0 * math.cos(azimuth)  # 70 degrees at the face, 120 at the back
        if polar < limit:
            return tuple(HEAD_RADIUS * c for c in d), d


def grow(rng, root, normal):
    """One strand: a list of POINTS points."""
    azimuth = math.atan2(root[0], root[2])
    length = rng.gauss(0.30 + 0.06 * (1 - math.cos(azimuth)) / 2, 0.025)
    length = max(0.12, length)
    comb = normalize((0.25 * root[0] / HEAD_RADIUS, -0.6, -1.0))
    direction = normalize(tuple(0.6 * n + 0.4 * c for n, c in zip(normal, comb)))
    # the spring: radius from 0 to its tip value, a pitch of its own, a phase and a hand
    tip_radius = rng.uniform(0.004, 0.008)
    turns = 4.0 * rng.uniform(0.75, 1.25)
    phase = rng.uniform(0, 2 * math.pi)
    hand = 1.0 if rng.random() < 0.6 else -1.0
    steps = 240
    ds = length / steps
    p = root
    centre_line = [p]
    frames = []
    for i in range(1, steps + 1):
        s = i / steps
        gravity = (0.0, -1.6 * s, 0.0)
        walk = (rng.gauss(0, 0.04), rng.gauss(0, 0.04), rng.gauss(0, 0.04))
        direction = normalize(tuple(d + ds * 25.0 * (g + w) for d, g, w in zip(direction, gravity, walk)))
        p = tuple(c + ds * d for c, d in zip(p, direction))
        r = math.sqrt(p[0] ** 2 + p[1] ** 2 + p[2] ** 2)
        shell = HEAD_RADIUS + 0.01 * min(1.0, 4 * s)
        if r < shell:  # out of the head
            p = tuple(c * shell / r for c in p)
        centre_line.append(p)
        frames.append(direction)
    frames.insert(0, frames[0])
    out = []
    side = normalize(cross(frames[0], (0.0, 1.0, 0.0)) if abs(frames[0][1]) < 0.95 else (1.0, 0.0, 0.0))
    for k in range(POINTS):
        j = round(k * steps / (POINTS - 1))
        s = j / steps
        t = frames[j]
        # carry the side direction along the strand (parallel transport, no twist)
        along = side[0] * t[0] + side[1] * t[1] + side[2] * t[2]
        side = normalize(tuple(sc - along * tc for sc, tc in zip(side, t)))
        up = cross(t, side)
        theta = hand * 2 * math.pi * turns * s + phase
        radius = tip_radius * s
        c = centre_line[j]
        out.append(tuple(c[i] + radius * (math.cos(theta) * side[i] + math.sin(theta) * up[i]) for i in range(3)))
    return out


def write_cyhair(path, strands):
    points = [c for strand in strands for p in strand for c in p]
    header = b"HAIR"
    header += struct.pack("<III", len(strands), len(points) // 3, 2)  # flags: points only
    header += struct.pack("<I", POINTS - 1)  # default segments
    header += struct.pack("<ff", 7e-5, 0.0)  # default thickness, transparency
    header += struct.pack("<fff", 0.25, 0.17, 0.10)  # default colour
    info = b"scripts/make-outside-groom.py"
    header += info + b"\0" * (88 - len(info))
    assert len(header) == 128
    with open(path, "wb") as f:
        f.write(header)
        f.write(struct.pack("<%df" % len(points), *points))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("out")
    parser.add_argument("--strands", type=int, default=40000)
    parser.add_argument("--seed", type=int, default=31)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    strands = []
    for _ in range(args.strands):
        root, normal = random_root(rng)
        strands.append(grow(rng, root, normal))
    write_cyhair(args.out, strands)
    print("%s: %d strands of %d points" % (args.out, len(strands), POINTS))


if __name__ == "__main__":
    main()
