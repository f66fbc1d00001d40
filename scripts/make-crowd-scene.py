#!/usr/bin/env python3
"""make-crowd-scene.py — writes assets/scenes/crowd.json: 100 groom instances of four
assets (three hair-mesh presets and the head_bob strand file) on heads, in rows of 1, 3,
5, ... 19 from close to the camera (the first row, 0.85 m away) to about 11 m away.

Entries of one asset share one groom (same file, LOD and cap), so the scene loads the four
grooms once. Run from the repository root: python3 scripts/make-crowd-scene.py
"""
import json
import math

ASSETS = [
    ("long_wavy", {"file": "../grooms/long_wavy.hairmesh.json"}),
    ("curly_medium", {"file": "../grooms/curly_medium.hairmesh.json"}),
    ("head_bob", {"strands_file": "../grooms/head_bob.hair", "scale": 0.01, "up": "z",
                  "appearance": {"strand_width": 4e-4, "min_hit_diameter_px": 1.0,
                                 "eumelanin": [3.0, 2.2], "pheomelanin": [0.4, 0.4]}}),
    ("fur_sphere", {"file": "../grooms/fur_sphere.hairmesh.json"}),
]
SKIN = [0.62, 0.43, 0.34]


def main():
    grooms, spheres, meshes = [], [], []
    k = 0
    for row in range(10):
        n = 2 * row + 1
        z = -0.5 * row ** 1.35  # rows spread out with distance
        dist = 0.85 - z
        half = 0.5 * dist  # the row spans about the view's width
        for i in range(n):
            x = 0.0 if n == 1 else -half + 2.0 * half * i / (n - 1)
            name, base = ASSETS[k % len(ASSETS)]
            rot = (k * 47) % 360 - 180 if k > 0 else 0  # the first faces the camera
            entry = dict(base)
            entry["lod"] = {"enabled": True}
            entry["name"] = "%s %d" % (name, k)
            t = {"translate": [round(x, 4) + 0.0, 0.0, round(z, 4) + 0.0], "rotate_y": rot}
            entry["transform"] = t
            grooms.append(entry)
            if name == "head_bob":
                meshes.append({"file": "../meshes/head.obj", "scale": 0.01, "up": "z",
                               "transform": dict(t), "color": SKIN})
            elif name == "fur_sphere":
                spheres.append({"center": t["translate"], "radius": 0.098,
                                "color": [0.35, 0.28, 0.22]})
            else:
                spheres.append({"center": t["translate"], "radius": 0.093, "color": SKIN})
            k += 1
    scene = {
        "resolution": [1280, 720],
        "camera": {"position": [0, 0.1, 0.85], "target": [0, 0.0, -6], "fov": 40},
        "background": [0.05, 0.055, 0.065],
        "ambient": [0.12, 0.12, 0.14],
        "lights": [
            {"type": "directional", "direction": [0.5, 0.8, 0.6], "color": [1.0, 0.95, 0.88],
             "intensity": 3.0},
            {"type": "directional", "direction": [-0.7, 0.2, -0.5], "color": [0.55, 0.65, 1.0],
             "intensity": 1.4},
        ],
        "segment_budget": 2000000,
        "max_strands": 65536,
        "spheres": spheres,
        "planes": [{"normal": [0, 1, 0], "offset": -0.2, "color": [0.3, 0.3, 0.3]}],
        "meshes": meshes,
        "grooms": grooms,
    }
    with open("assets/scenes/crowd.json", "w") as f:
        f.write("{\n")
        keys = list(scene)
        for j, key in enumerate(keys):
            v = scene[key]
            sep = "," if j + 1 < len(keys) else ""
            if isinstance(v, list) and v and isinstance(v[0], dict):
                f.write('  "%s": [\n' % key)
                for i, e in enumerate(v):
                    f.write("    " + json.dumps(e) + ("," if i + 1 < len(v) else "") + "\n")
                f.write("  ]%s\n" % sep)
            else:
                f.write('  "%s": %s%s\n' % (key, json.dumps(v), sep))
        f.write("}\n")


if __name__ == "__main__":
    main()
