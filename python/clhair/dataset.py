"""python -m clhair.dataset SPEC.json --out DIR: a hair data set rendered from a spec.

Each sample i draws, from a random generator seeded by (spec seed, i) alone, a groom, a view
(azimuth, elevation, field of view around a framing preset), a light rig and melanin
(eumelanin, pheomelanin), renders it with every layer and writes, in DIR:

- ``image/NNNNNN.png``: the colour (8-bit sRGB, as ``clhair render``);
- ``mask/NNNNNN.png``: the hair mask (hair alpha >= 0.5);
- ``orientation/NNNNNN.exr``: ``angle`` (radians in [0, pi), counter-clockwise from +x)
  and ``confidence`` (clhair.labels), and ``orientation/NNNNNN.png``, the angle as hue and
  the confidence as brightness;
- ``strand_map/NNNNNN.png``: the HairStep strand map (mask, direction);
- ``depth/NNNNNN.exr``: ``Z``, view depth (1e10 where nothing);
- ``record/NNNNNN.json``: what was drawn, written last: a sample with its record is done.

A second run with the same spec and folder renders only the samples without a record
(resume). Samples go out in batches (``"batch"`` in the spec); locally to ``--workers``
processes, one renderer each (``--devices`` lists the devices, one worker per entry), or
with ``--ray local`` / ``--ray ADDRESS`` as Ray tasks on actors that hold one renderer
each (one per CPU or GPU device). A sample depends on its index alone, so the files are the
same whichever way they were rendered.

The spec (JSON)::

    {"seed": 1, "samples": 100, "resolution": [512, 512], "batch": 4,
     "scene": {"background": [0.05, 0.05, 0.05], "ambient": [0.1, 0.1, 0.1]},
     "grooms": [{"strands_file": "a.hair", "scale": "auto"}, {"usd": "b.usda"}],
     "views": {"preset": "mid", "azimuth": [-90, 90], "elevation": [-10, 30],
               "fov": [30, 40]},
     "lighting": [[{"type": "directional", "direction": [0, 1, 1], "intensity": 3}]],
     "melanin": {"eumelanin": [0.2, 3.0], "pheomelanin": [0.05, 0.8]},
     "msaa": 1}

Ranges are [low, high] drawn uniformly (a single number is fixed); "grooms" entries are
scene groom entries (relative files are found beside the spec) or {"usd": path, ...} read
with clhair.io.read_usd; "lighting" is a list of light rigs, one drawn per sample.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from typing import Any, Dict, Iterable, List, Optional, Sequence

import numpy as np

from . import Error, Groom, Renderer, Scene, labels, write_exr, write_image

__all__ = ["Spec", "load_spec", "draw", "render_batch", "run", "main"]

KINDS = ("image", "mask", "orientation", "strand_map", "depth", "record")


class Spec:
    """A checked data-set spec (see the module)."""

    def __init__(self, data: Dict[str, Any], base_dir: str) -> None:
        self.raw = data
        self.base_dir = base_dir
        known = {"seed", "samples", "resolution", "batch", "scene", "grooms", "views",
                 "lighting", "melanin", "msaa"}
        unknown = sorted(set(data) - known)
        if unknown:
            raise Error(f"spec: unknown key \"{unknown[0]}\" (known: {', '.join(sorted(known))})")
        self.seed = int(data.get("seed", 0))
        self.samples = int(data.get("samples", 0))
        if self.samples < 1:
            raise Error(f"spec: samples must be at least 1, not {self.samples}")
        res = data.get("resolution", [512, 512])
        if not (isinstance(res, list) and len(res) == 2 and all(int(v) >= 1 for v in res)):
            raise Error(f"spec: resolution must be [width, height], not {res!r}")
        self.resolution = [int(res[0]), int(res[1])]
        self.batch = int(data.get("batch", 4))
        if self.batch < 1:
            raise Error(f"spec: batch must be at least 1, not {self.batch}")
        self.scene = dict(data.get("scene", {}))
        self.grooms = list(data.get("grooms", []))
        if not self.grooms:
            raise Error("spec: grooms: give at least one groom entry")
        self.views = dict(data.get("views", {}))
        self.lighting = list(data.get("lighting", []))
        self.melanin = dict(data.get("melanin", {}))
        self.msaa = int(data.get("msaa", 1))


def load_spec(path: str) -> Spec:
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except OSError as e:
        raise Error(f"{path}: cannot read ({e.strerror})") from None
    except json.JSONDecodeError as e:
        raise Error(f"{path}: not valid JSON (line {e.lineno}, column {e.colno}: {e.msg})") from None
    if not isinstance(data, dict):
        raise Error(f"{path}: the spec must be a JSON object")
    return Spec(data, os.path.dirname(os.path.abspath(path)))


def _uniform(rng: np.random.Generator, value: Any, default: float) -> float:
    if value is None:
        return float(default)
    if isinstance(value, (int, float)):
        return float(value)
    lo, hi = float(value[0]), float(value[1])
    return float(lo + (hi - lo) * rng.random())


def draw(spec: Spec, index: int) -> Dict[str, Any]:
    """What sample `index` shows: depends on the spec's seed and the index alone."""
    rng = np.random.default_rng([spec.seed, index])
    groom = int(rng.integers(len(spec.grooms)))
    v = spec.views
    view = {"preset": str(v.get("preset", "mid")),
            "azimuth": _uniform(rng, v.get("azimuth"), 0.0),
            "elevation": _uniform(rng, v.get("elevation"), 10.0),
            "fov": _uniform(rng, v.get("fov"), 35.0)}
    rig = int(rng.integers(len(spec.lighting))) if spec.lighting else -1
    m = spec.melanin
    melanin = None
    if m:
        melanin = {"eumelanin": _uniform(rng, m.get("eumelanin"), 1.3),
                   "pheomelanin": _uniform(rng, m.get("pheomelanin"), 0.1)}
    return {"index": index, "groom": groom, "view": view, "lighting": rig, "melanin": melanin}


class _Worker:
    """One renderer and the grooms read for it."""

    def __init__(self, spec: Spec, device: str = "") -> None:
        self.spec = spec
        self.renderer = Renderer(device=device)
        self.usd: Dict[int, Groom] = {}

    def scene(self, d: Dict[str, Any]) -> Scene:
        spec = self.spec
        entry = dict(spec.grooms[d["groom"]])
        if "usd" in entry:
            if d["groom"] not in self.usd:
                from .io import read_usd
                path = entry["usd"]
                path = path if os.path.isabs(path) else os.path.join(spec.base_dir, path)
                self.usd[d["groom"]] = read_usd(path)
            entry.pop("usd")
            entry["groom"] = self.usd[d["groom"]]
        if d["melanin"] is not None:
            look = dict(entry.get("appearance", {}))
            e, p = d["melanin"]["eumelanin"], d["melanin"]["pheomelanin"]
            look.update({"use_melanin": True, "eumelanin": [e, e], "pheomelanin": [p, p]})
            entry["appearance"] = look
        s = dict(spec.scene)
        s["resolution"] = spec.resolution
        s["camera"] = dict(d["view"])
        if d["lighting"] >= 0:
            s["lights"] = spec.lighting[d["lighting"]]
        s["grooms"] = [entry]
        return Scene(s, base_dir=spec.base_dir)

    def render(self, indices: Sequence[int], out: str) -> List[int]:
        tickets = []
        draws = [draw(self.spec, i) for i in indices]
        done = []
        # two frames in flight: the next frame renders while this one is written
        for d in draws:
            tickets.append(self.renderer.submit(self.scene(d), msaa=self.spec.msaa, aovs=True))
            if len(tickets) > 1:
                done.append(self._write(draws[len(done)], self.renderer.wait(tickets[len(done)]),
                                        out))
        while len(done) < len(draws):
            done.append(self._write(draws[len(done)], self.renderer.wait(tickets[len(done)]), out))
        return done

    def _write(self, d: Dict[str, Any], frame: Dict[str, Any], out: str) -> int:
        labels.compute(frame)
        name = f"{d['index']:06d}"
        p = {k: os.path.join(out, k, name) for k in KINDS}
        write_image(p["image"] + ".png", frame["rgba"])
        mask = frame["mask"].astype(np.float32)
        write_image(p["mask"] + ".png", np.dstack([mask, mask, mask, np.ones_like(mask)]))
        write_exr(p["orientation"] + ".exr", {"angle": frame["orientation"],
                                              "confidence": frame["confidence"]})
        write_image(p["orientation"] + ".png", orientation_colors(frame["orientation"],
                                                                  frame["confidence"]))
        sm = frame["strand_map"]
        write_image(p["strand_map"] + ".png", np.dstack([sm, np.ones(sm.shape[:2], np.float32)]))
        write_exr(p["depth"] + ".exr", {"Z": frame["depth"]})
        record = dict(d)
        record["groom_entry"] = {k: v for k, v in self.spec.grooms[d["groom"]].items()}
        record["resolution"] = self.spec.resolution
        record["hair_pixels"] = int(frame["mask"].sum())
        record["files"] = {k: f"{k}/{name}.{'json' if k == 'record' else 'png'}" for k in KINDS}
        record["files"]["orientation"] = f"orientation/{name}.exr"
        record["files"]["depth"] = f"depth/{name}.exr"
        tmp = p["record"] + ".json.tmp"
        with open(tmp, "w", encoding="utf-8") as f:
            json.dump(record, f, indent=1, sort_keys=True)
            f.write("\n")
        os.replace(tmp, p["record"] + ".json")
        return d["index"]


def orientation_colors(angle: np.ndarray, confidence: np.ndarray) -> np.ndarray:
    """The angle as hue (0..pi once around the wheel) and the confidence as value, linear
    RGBA for write_image."""
    h = angle / np.pi * 6.0
    c = np.clip(confidence, 0.0, 1.0)
    x = 1.0 - np.abs(np.mod(h, 2.0) - 1.0)
    k = np.floor(h).astype(int) % 6
    zero = np.zeros_like(h)
    one = np.ones_like(h)
    r = np.choose(k, [one, x, zero, zero, x, one])
    g = np.choose(k, [x, one, one, x, zero, zero])
    b = np.choose(k, [zero, zero, x, one, one, x])
    rgb = np.stack([r, g, b], axis=-1) * c[..., None]
    return np.dstack([rgb ** 2.2, np.ones_like(h)]).astype(np.float32)


def _todo(spec: Spec, out: str) -> List[int]:
    return [i for i in range(spec.samples)
            if not os.path.exists(os.path.join(out, "record", f"{i:06d}.json"))]


def _batches(todo: List[int], size: int) -> List[List[int]]:
    return [todo[k:k + size] for k in range(0, len(todo), size)]


class _Progress:
    """One line on standard error: done of total, the rate and the time left."""

    def __init__(self, total: int, quiet: bool) -> None:
        self.total, self.done, self.quiet = total, 0, quiet
        self.t0 = time.monotonic()

    def add(self, n: int) -> None:
        self.done += n
        if self.quiet:
            return
        dt = max(time.monotonic() - self.t0, 1e-9)
        rate = self.done / dt
        left = (self.total - self.done) / rate if rate > 0 else 0.0
        bar = int(30 * self.done / max(self.total, 1))
        sys.stderr.write(f"\r[{'#' * bar}{'.' * (30 - bar)}] {self.done}/{self.total} "
                         f"{rate * 3600:.0f} images/h, {left:.0f} s left ")
        if self.done >= self.total:
            sys.stderr.write("\n")
        sys.stderr.flush()


# a local worker process's renderer (multiprocessing)
_PROCESS_WORKER: Optional[_Worker] = None


def _process_init(spec_data: Dict[str, Any], base: str, devices: List[str]) -> None:
    import multiprocessing as mp
    global _PROCESS_WORKER
    ident = mp.current_process()._identity
    k = (ident[0] - 1) if ident else 0
    _PROCESS_WORKER = _Worker(Spec(spec_data, base), devices[k % len(devices)])


def _process_batch(args: Any) -> List[int]:
    indices, out = args
    assert _PROCESS_WORKER is not None
    return _PROCESS_WORKER.render(indices, out)


def run(spec: Spec, out: str, workers: int = 1, devices: Optional[List[str]] = None,
        ray_address: Optional[str] = None, quiet: bool = False) -> Dict[str, Any]:
    """Renders the samples of `spec` that `out` lacks; returns counts and times."""
    for k in KINDS:
        os.makedirs(os.path.join(out, k), exist_ok=True)
    todo = _todo(spec, out)
    batches = _batches(todo, spec.batch)
    devices = devices or [""]
    progress = _Progress(len(todo), quiet)
    t0 = time.monotonic()
    if ray_address is not None:
        _run_ray(spec, out, batches, workers, devices, ray_address, progress)
    elif workers <= 1:
        w = _Worker(spec, devices[0])
        for b in batches:
            progress.add(len(w.render(b, out)))
    else:
        import multiprocessing as mp
        ctx = mp.get_context("spawn")
        with ctx.Pool(workers, initializer=_process_init,
                      initargs=(spec.raw, spec.base_dir, devices)) as pool:
            for done in pool.imap_unordered(_process_batch, [(b, out) for b in batches]):
                progress.add(len(done))
    seconds = time.monotonic() - t0
    return {"rendered": len(todo), "skipped": spec.samples - len(todo), "seconds": seconds}


def _run_ray(spec: Spec, out: str, batches: List[List[int]], workers: int,
             devices: List[str], address: str, progress: _Progress) -> None:
    try:
        import ray
        from ray.util import ActorPool
    except ImportError as e:
        raise Error("--ray needs Ray: pip install ray") from e
    started = False
    if not ray.is_initialized():
        if address == "local":
            ray.init(num_cpus=max(workers, 1), include_dashboard=False,
                     object_store_memory=100 * 1024 * 1024,
                     log_to_driver=False, configure_logging=False)
        else:
            ray.init(address=address, log_to_driver=False, configure_logging=False)
        started = True
    try:
        gpus = float(ray.cluster_resources().get("GPU", 0))

        @ray.remote(num_cpus=1, num_gpus=1 if gpus >= 1 else 0)
        class RayWorker:
            def __init__(self, spec_data: Dict[str, Any], base: str, device: str) -> None:
                self.w = _Worker(Spec(spec_data, base), device)

            def render(self, indices: List[int], out_dir: str) -> List[int]:
                return self.w.render(indices, out_dir)

        n = max(1, workers)
        actors = [RayWorker.remote(spec.raw, spec.base_dir, devices[k % len(devices)])
                  for k in range(n)]
        pool = ActorPool(actors)
        for done in pool.map_unordered(lambda a, b: a.render.remote(b, out), batches):
            progress.add(len(done))
    finally:
        if started:
            ray.shutdown()


def main(argv: Optional[List[str]] = None) -> int:
    p = argparse.ArgumentParser(prog="python -m clhair.dataset",
                                description="render a hair data set from a spec")
    p.add_argument("spec", help="the data-set spec (JSON)")
    p.add_argument("--out", required=True, help="output folder (resumed when it exists)")
    p.add_argument("--workers", type=int, default=1,
                   help="renderers at once (local processes or Ray actors; default 1)")
    p.add_argument("--devices", default="",
                   help="comma-separated device selectors, one worker each in turn")
    p.add_argument("--ray", default=None, metavar="ADDRESS",
                   help="run as Ray tasks: \"local\" starts a cluster here, else its address")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    a = p.parse_args(argv)
    try:
        spec = load_spec(a.spec)
        devices = [d for d in a.devices.split(",") if d] if a.devices else None
        if a.workers < 1:
            raise Error(f"--workers must be at least 1, not {a.workers}")
        r = run(spec, a.out, workers=a.workers, devices=devices, ray_address=a.ray,
                quiet=a.quiet)
    except Error as e:
        print(f"clhair.dataset: {e}", file=sys.stderr)
        return 1
    rate = r["rendered"] / r["seconds"] * 3600 if r["seconds"] > 0 and r["rendered"] else 0.0
    print(f"{a.out}: {r['rendered']} samples rendered, {r['skipped']} already there, "
          f"{r['seconds']:.1f} s ({rate:.0f} images/h)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
