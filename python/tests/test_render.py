"""NumPy groom -> render -> arrays, frames in flight, and the command's files."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np

import clhair
from conftest import H, W, base_scene, straight_groom


def test_round_trip_arrays(renderer: clhair.Renderer) -> None:
    g = straight_groom(angle_deg=90.0)  # strands along +y, in the plane z = 0
    f = renderer.render(base_scene({"groom": g}))
    assert f["rgba"].shape == (H, W, 4) and f["rgba"].dtype == np.float32
    for k, shape in [("depth", (H, W)), ("alpha", (H, W)), ("tangent", (H, W, 3)),
                     ("motion", (H, W, 2)), ("strand", (H, W, 3))]:
        assert f[k].shape == shape and f[k].dtype == np.float32, k
    assert f["strand_id"].dtype == np.int32
    hair = f["alpha"] >= 0.5
    # 40 strands 3 mm apart across 12 cm seen from 0.6 m: a band in the middle of the frame
    assert hair.sum() > 100 and not hair[:, :5].any() and not hair[:, -5:].any()
    # every hair pixel names one of the 40 strands, and its tangent is +y (8+8-bit octahedral
    # code: under 0.017 rad off, see test_labels)
    ids = f["strand_id"][hair]
    assert ids.min() >= 0 and ids.max() < 40
    t = f["tangent"][hair]
    assert np.all(np.degrees(np.arccos(np.clip(t[:, 1], -1, 1))) < 1.0)
    # the strands lie in z = 0, 0.6 from the camera; the pixels hold the fibre's surface
    assert np.all(np.abs(f["depth"][hair] - 0.6) < 0.01)
    assert np.all(f["depth"][~(f["alpha"] > 0)] == np.float32(1e10))
    assert np.all(f["motion"] == 0)  # a still frame 1
    # nothing drawn where no hair: the background colour exactly
    empty = f["alpha"] == 0
    assert np.allclose(f["rgba"][empty][:, :3], [0.1, 0.2, 0.3], atol=1e-6)


def test_memory_groom_equals_its_file(renderer: clhair.Renderer, tmp_path: Path) -> None:
    g = straight_groom(widths=True, colors=True)
    g.write(tmp_path / "g.hair")
    from_memory = renderer.render(base_scene({"groom": g}))
    from_file = renderer.render(base_scene({"strands_file": str(tmp_path / "g.hair")}))
    for k in ("rgba", "depth", "alpha", "tangent", "motion", "strand"):
        assert np.array_equal(from_memory[k], from_file[k]), k


def test_frames_in_flight(renderer: clhair.Renderer) -> None:
    scenes = [clhair.Scene(base_scene({"groom": straight_groom(angle_deg=a)})) for a in (0, 45, 90)]
    tickets = [renderer.submit(s) for s in scenes]
    frames = [renderer.wait(t) for t in reversed(tickets)][::-1]
    for s, f in zip(scenes, frames):
        again = renderer.render(s)
        assert np.array_equal(f["rgba"], again["rgba"])
    assert not np.array_equal(frames[0]["rgba"], frames[2]["rgba"])


def test_every_array_equals_the_commands_files(renderer: clhair.Renderer, cli: Path,
                                               tmp_path: Path) -> None:
    g = straight_groom(angle_deg=60.0, tilt_deg=30.0, widths=True, colors=True)
    g.write(tmp_path / "g.hair")
    scene = base_scene({"strands_file": "g.hair"})
    (tmp_path / "s.json").write_text(json.dumps(scene))
    for out, extra in (("c.exr", ["--aov", "all"]), ("c.png", [])):
        subprocess.run([str(cli), "render", str(tmp_path / "s.json"), "-o", str(tmp_path / out),
                        "--quiet", *extra], check=True)
    f = renderer.render(str(tmp_path / "s.json"))
    mem = renderer.render(base_scene({"groom": g}))
    for k in ("rgba", "depth", "alpha", "tangent", "motion", "strand"):
        assert np.array_equal(f[k], mem[k]), k
    # 8-bit: the bytes
    names, png = clhair.read_image(tmp_path / "c.png")
    assert names == ["R", "G", "B", "A"] and png.dtype == np.uint8
    assert np.array_equal(png, clhair.encode_srgb8(f["rgba"]))
    # EXR: exact floats (channels the command stores as half, compared at half)
    names, exr = clhair.read_image(tmp_path / "c.exr")
    ch = {n: exr[..., i] for i, n in enumerate(names)}
    half = lambda a: a.astype(np.float16).astype(np.float32)  # noqa: E731
    want = {"R": half(f["rgba"][..., 0]), "G": half(f["rgba"][..., 1]),
            "B": half(f["rgba"][..., 2]), "A": half(f["rgba"][..., 3]), "Z": f["depth"],
            "hair.A": half(f["alpha"]), "motion.X": f["motion"][..., 0],
            "motion.Y": f["motion"][..., 1], "strand.groom": f["strand"][..., 0],
            "strand.id": f["strand"][..., 1], "strand.u": f["strand"][..., 2]}
    for c, axis in enumerate("XYZ"):
        want["tangent." + axis] = half(f["tangent"][..., c])
    assert set(want) == set(ch)
    for n, v in want.items():
        assert np.array_equal(ch[n], v), n
