"""Orientation and strand maps against the projected geometry of a synthetic groom.

The tangent layer holds each strand's tangent as an 8 + 8-bit octahedral code. Half a step
of the code is at most sqrt(2) / 255 in the octahedral plane; lifting to the octahedron
stretches a step by at most sqrt(3) and normalising onto the sphere by at most sqrt(3)
(|p| >= 1 / sqrt(3) on the octahedron), so a decoded tangent is within
3 sqrt(2) / 255 = 0.0166 rad of the true one. An image direction is off by at most that over
the sine of the tangent to the view ray (foreshortening).
"""

from __future__ import annotations

import numpy as np
import pytest

import clhair
from clhair import labels
from conftest import base_scene, straight_groom

TANGENT_BOUND = 3 * np.sqrt(2) / 255


def expected_directions(frame, t_world: np.ndarray, tilt_deg: float):
    """Per pixel: project the point where the pixel's ray meets the strands' plane and the
    point a millimetre along the strands, and take the image direction between them
    (x right, y up)."""
    cam = frame["camera"]
    m = np.asarray(cam["world_to_view"], dtype=np.float64)
    rot, trans = m[:, :3], m[:, 3]
    h, w = frame["alpha"].shape
    # the plane: through the origin, normal +z turned by the tilt about +x
    c, s = np.cos(np.radians(tilt_deg)), np.sin(np.radians(tilt_deg))
    normal_w = np.array([[1, 0, 0], [0, c, -s], [0, s, c]]) @ np.array([0.0, 0.0, 1.0])
    normal_v, origin_v = rot @ normal_w, trans  # view space (x right, y up, z forward)
    xs = (np.arange(w) + 0.5 - cam["cx"]) / cam["fx"]
    ys = -(np.arange(h) + 0.5 - cam["cy"]) / cam["fy"]
    ray = np.stack(np.broadcast_arrays(xs[None, :], ys[:, None], np.ones((h, 1))), axis=-1)
    depth = (origin_v @ normal_v) / (ray @ normal_v)
    p = ray * depth[..., None]
    q = p + 1e-3 * (rot @ t_world)

    def project(v):
        return np.stack([cam["cx"] + cam["fx"] * v[..., 0] / v[..., 2],
                         cam["cy"] - cam["fy"] * v[..., 1] / v[..., 2]], axis=-1)

    d = project(q) - project(p)
    d[..., 1] *= -1  # y up
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    tv = rot @ t_world
    sine = np.linalg.norm(np.cross(tv, ray / np.linalg.norm(ray, axis=-1, keepdims=True)), axis=-1)
    return d, sine


@pytest.mark.parametrize("angle,tilt", [(30.0, 0.0), (120.0, 50.0)])
def test_orientation_and_strand_map(renderer: clhair.Renderer, angle: float, tilt: float) -> None:
    g = straight_groom(angle_deg=angle, tilt_deg=tilt, strands=50)
    f = labels.compute(renderer.render(base_scene({"groom": g})))
    a = np.radians(angle)
    c, s = np.cos(np.radians(tilt)), np.sin(np.radians(tilt))
    t_world = np.array([[1, 0, 0], [0, c, -s], [0, s, c]]) @ np.array([np.cos(a), np.sin(a), 0])
    want, sine = expected_directions(f, t_world, tilt)
    mask = f["mask"]
    assert mask.sum() > 100
    assert np.array_equal(mask, f["alpha"] >= 0.5)
    bound = TANGENT_BOUND / sine[mask] + 1e-4
    # orientation: modulo pi
    want_angle = np.mod(np.arctan2(want[..., 1], want[..., 0]), np.pi)[mask]
    diff = np.abs(f["orientation"][mask] - want_angle)
    diff = np.minimum(diff, np.pi - diff)
    assert np.all(diff <= bound), (diff.max(), bound.min())
    assert np.all((f["orientation"] >= 0) & (f["orientation"] < np.pi))
    # confidence: alpha times the sine of the tangent to the ray (0 off the hair)
    conf_want = np.clip(f["alpha"], 0, 1)[mask] * sine[mask]
    assert np.all(np.abs(f["confidence"][mask] - conf_want) <= TANGENT_BOUND + 1e-4)
    assert np.all(f["confidence"][f["alpha"] == 0] == 0)
    # strand map: the mask in red, the root-to-tip direction (not modulo pi) in green, blue
    sm = f["strand_map"]
    assert np.array_equal(sm[..., 0] == 1, mask) and np.all(sm[~mask] == 0)
    got = sm[mask][:, 1:] * 2 - 1
    err = np.arccos(np.clip(np.sum(got * want[mask], axis=-1)
                            / np.linalg.norm(got, axis=-1), -1, 1))
    assert np.all(err <= bound), err.max()


def test_device_labels_match_the_numpy_reference(renderer: clhair.Renderer) -> None:
    """render() computes the labels on the device (kernels/labels.cl); labels.py's NumPy
    functions compute them on the host from the same tangent and alpha layers."""
    g = straight_groom(angle_deg=120.0, tilt_deg=50.0, strands=50)
    f = renderer.render(base_scene({"groom": g}))
    assert {"mask", "orientation", "confidence", "strand_map"} <= set(f)
    angle, confidence = labels.orientation(f)
    has = confidence > 0
    assert has.sum() > 100
    diff = np.abs(f["orientation"] - angle)
    diff = np.minimum(diff, np.pi - diff)  # modulo pi: 0 and pi are one angle
    assert diff[has].max() < 1e-4
    assert np.abs(f["confidence"] - confidence).max() < 1e-5
    assert np.array_equal(f["mask"], f["alpha"] >= labels.MASK_ALPHA)
    assert np.abs(f["strand_map"] - labels.strand_map(f)).max() < 1e-5
    # compute() keeps what the device gave
    assert labels.compute(f)["orientation"] is f["orientation"]
