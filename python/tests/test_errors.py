"""Bad input: one clhair.Error whose message is one line naming what failed."""

from __future__ import annotations

import numpy as np
import pytest

import clhair
from conftest import base_scene, straight_groom

P = np.zeros((4, 3), dtype=np.float32)
P[:, 1] = np.linspace(0, 0.1, 4)
C = np.array([2, 2], dtype=np.int32)


def one_line(e: pytest.ExceptionInfo) -> str:
    msg = str(e.value)
    assert "\n" not in msg and msg
    return msg


@pytest.mark.parametrize("points,counts,kw,words", [
    (P.astype(np.float64), C, {}, ["points", "float64", "float32"]),
    (P[:, :2].copy(), C, {}, ["points", "(4, 2)", "(N, 3)"]),
    (np.zeros((0, 3), np.float32), np.zeros(0, np.int32), {}, ["points", "empty"]),
    (np.where(np.arange(12).reshape(4, 3) == 4, np.nan, P).astype(np.float32), C, {},
     ["points", "[1, 1]", "not finite"]),
    (P, np.array([2, 3], np.int32), {}, ["counts", "5", "4"]),
    (P, np.array([1, 3], np.int32), {}, ["counts[0]", "1"]),
    (P, C.astype(np.float32), {}, ["counts", "float32", "integer"]),
    (P, C, {"widths": np.ones(3, np.float32)}, ["widths", "3", "4"]),
    (P, C, {"colors": np.ones((4, 3), np.float64)}, ["colors", "float64"]),
    (P.tolist(), C, {}, ["points", "list", "numpy.ndarray"]),
    (P, C, {"widths": np.array([1, 1, 0, 1], np.float32)}, ["widths[2]", "not positive"]),
])
def test_bad_groom(points, counts, kw, words) -> None:
    with pytest.raises(clhair.Error) as e:
        clhair.Groom(points, counts, **kw)
    msg = one_line(e)
    for w in words:
        assert w in msg, (w, msg)


def test_bad_scene_and_options(renderer: clhair.Renderer) -> None:
    g = straight_groom()
    s = base_scene({"groom": g})
    s["resolutoin"] = [8, 8]
    with pytest.raises(clhair.Error) as e:
        clhair.Scene(s)
    assert "resolutoin" in one_line(e)
    with pytest.raises(clhair.Error) as e:
        clhair.Scene(base_scene({"groom": "not a groom"}))
    assert "grooms[0].groom" in one_line(e)
    with pytest.raises(clhair.Error) as e:
        clhair.Scene(base_scene({"strands_file": "missing.hair"}))
    assert "missing.hair" in one_line(e) and "does not exist" in str(e.value)
    with pytest.raises(clhair.Error) as e:
        renderer.render(base_scene({"groom": g}), msaa=3)
    assert "msaa" in one_line(e) and "3" in str(e.value)
    with pytest.raises(clhair.Error) as e:
        renderer.wait(123456)
    assert "123456" in one_line(e)


def test_unknown_device() -> None:
    with pytest.raises(clhair.Error) as e:
        clhair.Renderer(device="no-such-device-xyz")
    assert "no-such-device-xyz" in one_line(e)
