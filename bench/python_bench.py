"""The Python binding's cost over the C++ library for the same frame, and data-set throughput.

    python bench/python_bench.py [--size 512] [--frames 10] [--rounds 3]
    python bench/python_bench.py --dataset 8 [--ray]

Render: the default scene (assets/scenes/default.json) at SIZE x SIZE with every layer
(aovs), rendered `frames` times by the library's own loop (Renderer::render on the same
still, inside the module, no Python in the loop) and `frames` times by Renderer.render from
Python (dicts of NumPy arrays back); rounds alternate, and the medians are compared.

Data set: a spec of `--dataset N` samples of head_bob at SIZE x SIZE with every label,
rendered by one local worker and, with --ray, by Ray with two local workers; images per hour.
Reported, never asserted (bench/README.md, "Python").
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import tempfile
import time
from pathlib import Path

import clhair
from clhair import dataset

ROOT = Path(__file__).resolve().parents[1]


def render_overhead(size: int, frames: int, rounds: int) -> None:
    scene = json.loads((ROOT / "assets/scenes/default.json").read_text())
    scene["resolution"] = [size, size]
    s = clhair.Scene(scene, base_dir=str(ROOT / "assets/scenes"))
    r = clhair.Renderer()
    for _ in range(2):
        r.render(s)
    lib, py = [], []
    for _ in range(rounds):
        lib.append(r.bench_library(s, frames) / frames)
        t0 = time.perf_counter()
        for _ in range(frames):
            r.render(s)
        py.append((time.perf_counter() - t0) / frames)
    ml, mp = statistics.median(lib), statistics.median(py)
    print(f"device: {r.device_name}")
    print(f"{size}x{size} with aovs: library {ml * 1e3:.1f} ms/frame, Python {mp * 1e3:.1f} "
          f"ms/frame, ratio {mp / ml:.3f} (rounds: lib {[round(x * 1e3, 1) for x in lib]}, "
          f"py {[round(x * 1e3, 1) for x in py]})")


def dataset_throughput(size: int, samples: int, ray: bool) -> None:
    tmp = Path(tempfile.mkdtemp(prefix="clhair-ds-"))
    try:
        spec = {
            "seed": 3, "samples": samples, "resolution": [size, size], "batch": 2,
            "scene": {"background": [0.05, 0.05, 0.06], "ambient": [0.12, 0.12, 0.14],
                      "spheres": [{"center": [0, 0, 0], "radius": 0.093,
                                   "color": [0.62, 0.43, 0.34]}]},
            "grooms": [{"strands_file": str(ROOT / "assets/grooms/head_bob.hair"),
                        "scale": 0.01, "up": "z",
                        "appearance": {"strand_width": 0.0004, "min_hit_diameter_px": 1.0}}],
            "views": {"preset": "mid", "azimuth": [-90, 90], "elevation": [-10, 30],
                      "fov": [30, 40]},
            "lighting": [[{"type": "directional", "direction": [0.5, 0.8, 0.6], "intensity": 3}],
                         [{"type": "directional", "direction": [-0.7, 0.2, -0.5],
                           "intensity": 2}]],
            "melanin": {"eumelanin": [0.2, 3.0], "pheomelanin": [0.05, 0.8]},
        }
        (tmp / "spec.json").write_text(json.dumps(spec))
        s = dataset.load_spec(str(tmp / "spec.json"))
        runs = [("1 local worker", {"workers": 1})]
        if ray:
            runs.append(("Ray, 2 local workers", {"workers": 2, "ray_address": "local"}))
        for name, kw in runs:
            out = tmp / name.replace(" ", "_").replace(",", "")
            started = 0.0
            if "ray_address" in kw:  # the cluster's start-up, timed apart
                import ray
                t0 = time.perf_counter()
                ray.init(num_cpus=2, include_dashboard=False,
                         object_store_memory=100 * 1024 * 1024, log_to_driver=False)
                started = time.perf_counter() - t0
            t0 = time.perf_counter()
            r = dataset.run(s, str(out), quiet=True, **kw)
            dt = time.perf_counter() - t0
            print(f"{size}x{size}, {samples} samples, {name}: {dt:.1f} s wall "
                  f"(renderers' start-up included; Ray's cluster {started:.1f} s more), "
                  f"{r['rendered'] / dt * 3600:.0f} images/h")
            if started:
                ray.shutdown()
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--size", type=int, default=512)
    p.add_argument("--frames", type=int, default=10)
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--dataset", type=int, default=0, help="samples (0: the render benchmark)")
    p.add_argument("--ray", action="store_true")
    a = p.parse_args()
    os.environ.setdefault("RAY_DEDUP_LOGS", "0")
    if a.dataset:
        dataset_throughput(a.size, a.dataset, a.ray)
    else:
        render_overhead(a.size, a.frames, a.rounds)


if __name__ == "__main__":
    main()
