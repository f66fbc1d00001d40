"""python -m clhair.dataset: files, resume, determinism, and Ray against local runs."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Dict

import numpy as np
import pytest

import clhair
from clhair import dataset
from conftest import straight_groom

SAMPLES = 4


def make_spec(tmp_path: Path) -> Path:
    straight_groom(angle_deg=80, strands=30, colors=False).write(tmp_path / "a.hair")
    straight_groom(angle_deg=20, tilt_deg=40, strands=30).write(tmp_path / "b.hair")
    spec = {
        "seed": 7, "samples": SAMPLES, "resolution": [64, 48], "batch": 2,
        "scene": {"background": [0.1, 0.1, 0.1], "ambient": [0.1, 0.1, 0.1]},
        "grooms": [{"strands_file": "a.hair", "appearance": {"min_hit_diameter_px": 1.0}},
                   {"strands_file": "b.hair", "appearance": {"min_hit_diameter_px": 1.0}}],
        "views": {"preset": "mid", "azimuth": [-40, 40], "elevation": [-10, 20], "fov": [30, 40]},
        "lighting": [[{"type": "directional", "direction": [0, 1, 1], "intensity": 3}],
                     [{"type": "directional", "direction": [1, 0.2, 0.5], "intensity": 2}]],
        "melanin": {"eumelanin": [0.2, 3.0], "pheomelanin": [0.05, 0.8]},
    }
    (tmp_path / "spec.json").write_text(json.dumps(spec))
    return tmp_path / "spec.json"


def files(out: Path) -> Dict[str, bytes]:
    return {str(p.relative_to(out)): p.read_bytes() for p in sorted(out.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def first_run(tmp_path_factory) -> tuple:
    tmp = tmp_path_factory.mktemp("ds")
    spec = make_spec(tmp)
    r = subprocess.run([sys.executable, "-m", "clhair.dataset", str(spec), "--out",
                        str(tmp / "a")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert f"{SAMPLES} samples rendered, 0 already there" in r.stdout
    assert "images/h" in r.stderr  # the progress line
    return spec, tmp / "a"


def test_files_and_records(first_run) -> None:
    spec, out = first_run
    got = files(out)
    for i in range(SAMPLES):
        n = f"{i:06d}"
        for k in ("image/%s.png", "mask/%s.png", "orientation/%s.exr", "orientation/%s.png",
                  "strand_map/%s.png", "depth/%s.exr", "record/%s.json"):
            assert k % n in got, k % n
        rec = json.loads(got[f"record/{n}.json"])
        assert rec["index"] == i and rec == {**rec, **dataset.draw(dataset.load_spec(str(spec)), i)}
        names, mask = clhair.read_image(out / f"mask/{n}.png")
        assert rec["hair_pixels"] == int((mask[..., 0] == 255).sum()) > 0
        names, orient = clhair.read_image(out / f"orientation/{n}.exr")
        angle = orient[..., names.index("angle")]
        assert np.all((angle >= 0) & (angle < np.pi))
    # the draws differ between samples and stay inside the spec's ranges
    draws = [dataset.draw(dataset.load_spec(str(spec)), i) for i in range(SAMPLES)]
    assert len({d["view"]["azimuth"] for d in draws}) == SAMPLES
    assert all(-40 <= d["view"]["azimuth"] <= 40 and 0.2 <= d["melanin"]["eumelanin"] <= 3.0
               for d in draws)


def test_resume_renders_only_what_is_missing(first_run, tmp_path: Path) -> None:
    spec, out = first_run
    before = files(out)
    os.remove(out / "record/000002.json")
    os.remove(out / "image/000002.png")
    r = dataset.run(dataset.load_spec(str(spec)), str(out), quiet=True)
    assert r["rendered"] == 1 and r["skipped"] == SAMPLES - 1
    assert files(out) == before


def test_identical_however_it_ran(first_run, tmp_path: Path) -> None:
    spec, out = first_run
    s = dataset.load_spec(str(spec))
    dataset.run(s, str(tmp_path / "again"), quiet=True)
    assert files(tmp_path / "again") == files(out)
    dataset.run(s, str(tmp_path / "two"), workers=2, quiet=True)  # two local processes
    assert files(tmp_path / "two") == files(out)
    pytest.importorskip("ray", reason="Ray is not installed (pip install ray)")
    dataset.run(s, str(tmp_path / "ray"), workers=2, ray_address="local", quiet=True)
    assert files(tmp_path / "ray") == files(out)
