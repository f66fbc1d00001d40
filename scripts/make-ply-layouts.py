#!/usr/bin/env python3
"""make-ply-layouts.py - the same strands in the PLY layouts scan tools write, and in cyHair.

Writes into OUT_DIR:
  strand_and_edge.ply  hapPLY's layout: element vertex (float x, y, z; uchar red, green, blue),
                       element strand (ushort nsegs) and element edge (int vertex1, vertex2)
  strand.ply           the same without the edge element
  edge.ply             the same without the strand element
  twin.hair            the same strands in cyHair (colours linear: the 8-bit sRGB decoded)
  NAME.json            for each file, a scene drawing it (the same camera and lights)
The headers are hapPLY's byte for byte: "format binary_little_endian 1.0", its comment line
"Written with hapPLY (https://github.com/nmwsharp/happly)", elements and properties in the
order written, "end_header". With --seeds, also the broken twins (an edge missing inside a
strand, a count of an unknown name) and small files for the fuzzer's seed corpus.

  scripts/make-ply-layouts.py OUT_DIR [--strands N] [--points P] [--seeds]

The contact sheet in docs/images/ply_layouts_sheet.png (left to right: strand_and_edge,
strand, edge, twin):
  d=build/ply; scripts/make-ply-layouts.py $d
  for n in strand_and_edge strand edge twin; do build/clhair render $d/$n.json -o $d/$n.png; done
  oiiotool $d/strand_and_edge.png $d/strand.png $d/edge.png $d/twin.png --mosaic 4x1 \
      -o docs/images/ply_layouts_sheet.png
Pure Python (struct, math): no numpy needed.
"""

import argparse
import json
import math
import os
import struct

HAPPLY_COMMENT = "comment Written with hapPLY (https://github.com/nmwsharp/happly)\n"


def strands(count, points):
    """Hanging strands on a ring (metres) and 8-bit sRGB colours, blonde at the root to
    lighter at the tip, varying from strand to strand."""
    xyz, rgb = [], []
    for i in range(count):
        a = 2.0 * math.pi * i / count
        for k in range(points):
            t = k / (points - 1)
            xyz.append((0.07 * math.cos(a) + 0.01 * t * math.sin(3 * a),
                        0.12 - 0.2 * t, 0.07 * math.sin(a) + 0.015 * t * t))
            v = (i * 37) % 23
            rgb.append((min(255, 150 + int(80 * t) + v), min(255, 115 + int(70 * t) + v // 2),
                        60 + int(40 * t)))
    return xyz, rgb


def happly(xyz, rgb, points, strand=True, edge=True, count_name="nsegs"):
    n = len(xyz) // points
    head = ("ply\nformat binary_little_endian 1.0\n" + HAPPLY_COMMENT +
            "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
            "property uchar red\nproperty uchar green\nproperty uchar blue\n" % len(xyz))
    if strand:
        head += "element strand %d\nproperty ushort %s\n" % (n, count_name)
    edges = [(s * points + k, s * points + k + 1) for s in range(n) for k in range(points - 1)]
    if edge:
        head += "element edge %d\nproperty int vertex1\nproperty int vertex2\n" % len(edges)
    head += "end_header\n"
    body = b"".join(struct.pack("<3f3B", *p, *c) for p, c in zip(xyz, rgb))
    if strand:
        body += struct.pack("<%dH" % n, *([points - 1] * n))
    if edge:
        body += b"".join(struct.pack("<2i", *e) for e in edges)
    return head.encode("ascii") + body, edges


def srgb_to_linear(c8):
    c = c8 / 255.0
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def cyhair(xyz, rgb, points):
    n = len(xyz) // points
    info = b"twin".ljust(88, b"\0")
    head = b"HAIR" + struct.pack("<4I5f", n, len(xyz), 2 | 16, points - 1, 1.0, 0.0, 1.0, 1.0,
                                 1.0) + info
    body = b"".join(struct.pack("<3f", *p) for p in xyz)
    body += b"".join(struct.pack("<3f", *(srgb_to_linear(c) for c in col)) for col in rgb)
    return head + body


def write(path, data):
    with open(path, "wb") as f:
        f.write(data)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--strands", type=int, default=400)
    ap.add_argument("--points", type=int, default=16)
    ap.add_argument("--seeds", action="store_true")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    xyz, rgb = strands(a.strands, a.points)
    files = {"strand_and_edge.ply": dict(), "strand.ply": dict(edge=False),
             "edge.ply": dict(strand=False)}
    for name, kw in files.items():
        write(os.path.join(a.out, name), happly(xyz, rgb, a.points, **kw)[0])
    write(os.path.join(a.out, "twin.hair"), cyhair(xyz, rgb, a.points))
    for name in list(files) + ["twin.hair"]:
        scene = {"resolution": [240, 240], "background": [0.06, 0.06, 0.07],
                 "ambient": [0.12, 0.12, 0.13],
                 "camera": {"position": [0, 0.02, 0.5], "target": [0, 0.02, 0], "fov": 40},
                 "lights": [{"type": "directional", "direction": [0.4, 0.8, 0.6],
                             "intensity": 2.6}],
                 "grooms": [{"strands_file": name, "appearance": {"min_hit_diameter_px": 1}}]}
        with open(os.path.join(a.out, name.split(".")[0] + ".json"), "w") as f:
            json.dump(scene, f, indent=1)
    if a.seeds:
        small_xyz, small_rgb = strands(3, 4)
        for name, kw in files.items():
            write(os.path.join(a.out, "valid_happly_" + name), happly(small_xyz, small_rgb, 4,
                                                                     **kw)[0])
        data, edges = happly(small_xyz, small_rgb, 4)
        # an edge missing inside strand 0: its first edge repeats its second
        at = len(data) - 8 * len(edges)
        write(os.path.join(a.out, "bad_happly_edges_disagree.ply"),
              data[:at] + struct.pack("<2i", 1, 2) + data[at + 8:])
        write(os.path.join(a.out, "bad_happly_count_name.ply"),
              happly(small_xyz, small_rgb, 4, edge=False, count_name="nseg_")[0])


if __name__ == "__main__":
    main()
