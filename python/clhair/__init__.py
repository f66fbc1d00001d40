"""clhair from Python: grooms in and images out as NumPy arrays.

A :class:`Renderer` opens one OpenCL device and keeps it, its compiled kernels and the
device forms of the grooms it has drawn across calls, so a frame costs its rendering and
nothing else. Scenes are dicts in the scene-file schema (docs/scene-format.md) or paths to
scene files; grooms come from NumPy arrays (:class:`Groom`) without a file in between.
``render()`` returns a dict of NumPy arrays that own the frame's memory.

Every failure is a :class:`clhair.Error` whose message is the one line the command prints.
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _clhair
from ._clhair import Error

__all__ = ["Error", "Groom", "Scene", "Renderer", "write_image", "write_exr", "read_image",
           "encode_srgb8"]

SceneLike = Union["Scene", Mapping[str, Any], str, "os.PathLike[str]"]


def _array(value: Any, what: str) -> np.ndarray:
    if not isinstance(value, np.ndarray):
        raise Error(f"{what}: a {type(value).__name__}, expected a numpy.ndarray")
    return value


class Groom:
    """Explicit strands held in memory.

    Args:
        points: (N, 3) float32, object space, strand after strand (root first).
        counts: (S,) integers, the points of each strand (each >= 2, adding up to N).
        widths: optional (N,) float32 fibre width per point (object units, > 0).
        colors: optional (N, 3) float32 linear RGB per point.
        name: the groom's name (error lines and the scene's records).

    The arrays are checked and copied once; a non-float32 dtype, a wrong shape, an empty
    array, a NaN or infinity, or counts that do not add up raise :class:`clhair.Error`.
    """

    def __init__(self, points: np.ndarray, counts: np.ndarray,
                 widths: Optional[np.ndarray] = None, colors: Optional[np.ndarray] = None,
                 name: str = "groom") -> None:
        points = _array(points, "points")
        counts = _array(counts, "counts")
        widths = None if widths is None else _array(widths, "widths")
        colors = None if colors is None else _array(colors, "colors")
        self._handle = _clhair._make_groom(points, counts, widths, colors, str(name))
        self.name = str(name)
        self.points = points
        self.counts = counts
        self.widths = widths
        self.colors = colors

    @property
    def strand_count(self) -> int:
        return int(self._handle.strands)

    @property
    def point_count(self) -> int:
        return int(self._handle.points)

    def write(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Writes the strands to a strand file: .hair (cyHair: widths and colours kept),
        .ply (colours kept) or .data (USC-HairSalon: points only)."""
        _clhair._write_strands(self._handle, os.fspath(path))

    def __repr__(self) -> str:
        return f"Groom({self.name!r}, {self.strand_count} strands, {self.point_count} points)"


def _json_default(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise Error(f"scene: a {type(value).__name__} cannot stand in a scene dict "
                "(only JSON values, and clhair.Groom as a groom entry's \"groom\")")


class Scene:
    """A scene read once and rendered any number of times.

    Args:
        source: a dict in the scene-file schema, or the path of a scene file.
        grooms: in-memory grooms appended to the scene's "grooms" (default placement and
            appearance). A dict's groom entry may also hold ``"groom": Groom`` in place of
            ``"strands_file"``, with the other keys of a strand-file entry ("appearance",
            "scale", "up", "transform", "lod", ...).
        base_dir: where relative file names in a dict are found (default: the current
            folder).
    """

    def __init__(self, source: Union[Mapping[str, Any], str, "os.PathLike[str]"],
                 grooms: Optional[Sequence[Groom]] = None,
                 base_dir: Optional[Union[str, "os.PathLike[str]"]] = None) -> None:
        if isinstance(source, (str, os.PathLike)):
            if grooms:
                raise Error("scene: grooms= goes with a scene dict, not a scene file "
                            "(load the file with json and pass the dict)")
            self._handle = _clhair._load_scene(os.fspath(source))
            return
        if not isinstance(source, Mapping):
            raise Error(f"scene: a {type(source).__name__}, expected a dict or a path")
        scene = dict(source)
        memory: Dict[str, Any] = {}
        entries: List[Any] = []
        given = scene.get("grooms", [])
        if not isinstance(given, (list, tuple)):
            raise Error("scene: grooms: must be a list")
        for extra in grooms or []:
            given = list(given) + [extra]
        for i, entry in enumerate(given):
            if isinstance(entry, Groom):
                entry = {"groom": entry}
            if isinstance(entry, Mapping) and "groom" in entry:
                g = entry["groom"]
                if not isinstance(g, Groom):
                    raise Error(f"scene: grooms[{i}].groom: a {type(g).__name__}, "
                                "expected a clhair.Groom")
                key = f"memory:{i}"
                memory[key] = g._handle
                entry = {k: v for k, v in entry.items() if k != "groom"}
                entry["strands_file"] = key
                entry.setdefault("name", g.name)
            entries.append(entry)
        if entries:
            scene["grooms"] = entries
        text = json.dumps(scene, default=_json_default)
        base = os.fspath(base_dir) if base_dir is not None else os.getcwd()
        self._handle = _clhair._load_scene_json(text, "scene", base, memory)

    @property
    def width(self) -> int:
        return int(self._handle.width)

    @property
    def height(self) -> int:
        return int(self._handle.height)

    @property
    def warnings(self) -> List[str]:
        return list(self._handle.warnings)


def _scene(scene: SceneLike, grooms: Optional[Sequence[Groom]]) -> Scene:
    if isinstance(scene, Scene):
        if grooms:
            raise Error("scene: grooms= goes with a scene dict; a Scene has its grooms")
        return scene
    return Scene(scene, grooms=grooms)


class Renderer:
    """One OpenCL device with its compiled kernels, kept across frames.

    Args:
        device: "" (the first device with 64-bit atomics, GPUs first), "P:D" indices, or a
            device or platform name substring (as ``clhair render --device``).
        subgroup: "" (automatic) or a sub-group backend name to force.
        cache_dir: compiled-program cache folder ("" default, "off" none).
    """

    def __init__(self, device: str = "", subgroup: str = "", cache_dir: str = "") -> None:
        self._r = _clhair._Renderer(device, subgroup, cache_dir)

    @property
    def device_name(self) -> str:
        return str(self._r.device_name)

    @property
    def frames_in_flight(self) -> int:
        return int(self._r.frames_in_flight)

    @frames_in_flight.setter
    def frames_in_flight(self, n: int) -> None:
        self._r.frames_in_flight = int(n)

    def submit(self, scene: SceneLike, *, grooms: Optional[Sequence[Groom]] = None,
               frame: float = 1, msaa: int = 1, aovs: bool = True, lod: str = "auto",
               filter: str = "auto", quality: str = "", ao: bool = True) -> int:
        """Enqueues a frame and returns its ticket without waiting for the device.

        Options mean what the command's flags of the same name mean: ``msaa`` 1, 2, 4 or 8;
        ``lod`` "auto", "on" or "off"; ``filter`` "auto", "on", "off", "lipp" or "huang";
        ``quality`` "" (the scene's), "draft" or "good"; ``ao`` baked ambient occlusion.
        ``aovs`` (default True) adds the layers of ``clhair render --aov all``.
        """
        s = _scene(scene, grooms)
        return int(self._r.submit(s._handle, float(frame), int(msaa), bool(aovs), str(lod),
                                  str(filter), str(quality), bool(ao)))

    def wait(self, ticket: int) -> Dict[str, Any]:
        """The frame of ``ticket`` (blocks until the device has finished it) as a dict:

        - ``rgba`` (H, W, 4) float32: linear colour composited over the background (alpha 1).
        - ``depth`` (H, W) float32: view depth (1e10 where nothing; without aovs +inf).
        - with aovs, the labels computed on the device (``clhair.labels``): ``mask`` (H, W)
          bool, ``orientation`` and ``confidence`` (H, W), ``strand_map`` (H, W, 3);
        - with aovs: ``alpha`` (H, W) the hair's coverage; ``tangent`` (H, W, 3) world unit
          tangent (0 where no strand); ``motion`` (H, W, 2) pixels to the previous frame
          (x right, y up); ``strand`` (H, W, 3) groom index, strand index, u (-1 where none;
          MSAA 1 only) and ``strand_id`` (H, W) int32 from it; ``hair`` and ``opaque``
          (H, W, 4) the hair's premultiplied colour and the opaque scene's.
        - ``camera``: ``world_to_view`` (3, 4), ``fx``, ``fy``, ``cx``, ``cy`` (pixels; a view
          point projects to x = cx + fx X / Z, y = cy - fy Y / Z).
        """
        out = self._r.wait(int(ticket))
        if "strand" in out:
            out["strand_id"] = out["strand"][..., 1].astype(np.int32)
        return out

    def render(self, scene: SceneLike, **options: Any) -> Dict[str, Any]:
        """One frame: ``wait(submit(scene, **options))``."""
        return self.wait(self.submit(scene, **options))

    def release_grooms(self) -> None:
        """Frees the device forms of grooms the last frame did not draw."""
        self._r.release_grooms()

    def bench_library(self, scene: SceneLike, n: int, **options: Any) -> float:
        """Seconds the C++ library's own loop takes for ``n`` renders of the frame (the
        baseline of the Python overhead benchmark)."""
        s = _scene(scene, options.pop("grooms", None))
        o = {"frame": 1, "msaa": 1, "aovs": True, "lod": "auto", "filter": "auto",
             "quality": "", "ao": True}
        o.update(options)
        return float(self._r.bench_library(s._handle, float(o["frame"]), int(o["msaa"]),
                                           bool(o["aovs"]), str(o["lod"]), str(o["filter"]),
                                           str(o["quality"]), bool(o["ao"]), int(n)))


def write_image(path: Union[str, "os.PathLike[str]"], rgba: np.ndarray) -> None:
    """Writes (H, W, 4) float32 linear RGBA as the command does: 8-bit sRGB for PNG, linear
    for EXR."""
    _clhair._write_image(os.fspath(path), _array(rgba, "rgba"))


def write_exr(path: Union[str, "os.PathLike[str]"], channels: Mapping[str, np.ndarray],
              half: Iterable[str] = ()) -> None:
    """Writes (H, W) float32 planes as one OpenEXR file, channels in the order given; the
    names in ``half`` are stored as 16-bit floats."""
    halves = set(half)
    names = list(channels)
    _clhair._write_channels(os.fspath(path), names, [_array(channels[n], n) for n in names],
                            [n in halves for n in names])


def read_image(path: Union[str, "os.PathLike[str]"]) -> "tuple[List[str], np.ndarray]":
    """An image file as stored: (channel names, (H, W, C) uint8 for 8-bit files, else
    float32)."""
    names, pixels = _clhair._read_image(os.fspath(path))
    return list(names), pixels


def encode_srgb8(rgba: np.ndarray) -> np.ndarray:
    """(H, W, 4) float32 linear RGBA to the bytes the 8-bit writers store."""
    return _clhair._encode_srgb8(_array(rgba, "rgba"))
