#!/usr/bin/env bash
# make-groom-sheet.sh — the contact sheet of downloaded-style grooms (docs/images/
# groom_files_sheet.png): files made with clhair and a few lines of Python, rendered with
# their files' own appearance and with children grown from guides.
#
#   scripts/make-groom-sheet.sh [BUILD_DIR]   (default build; writes BUILD_DIR/sheet/)
#
# The files: a guides-only TressFX file exported from the long_wavy hair mesh (3000 guides),
# a cyHair file with blonde per-point colours and a header thickness (long_wavy's strands,
# recoloured here), and a PLY file exported from the curly_medium hair mesh. Each render's
# strand-pass time is printed (clhair render's stage table). Needs Python 3 with NumPy and
# oiiotool (openimageio-tools).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
clhair=$build/clhair
out=$build/sheet
mkdir -p "$out"
cd "$out"

grooms=$root/assets/grooms
echo "{\"grooms\": [{\"file\": \"$grooms/long_wavy.hairmesh.json\", \"strands\": 3000}]}" > guides_scene.json
echo "{\"grooms\": [{\"file\": \"$grooms/long_wavy.hairmesh.json\", \"strands\": 30000}]}" > wavy_scene.json
echo "{\"grooms\": [{\"file\": \"$grooms/curly_medium.hairmesh.json\", \"strands\": 30000}]}" > curly_scene.json
"$clhair" export-strands guides_scene.json -o guides.tfx
"$clhair" export-strands wavy_scene.json -o wavy.hair
"$clhair" export-strands curly_scene.json -o curly.ply

# blonde per-point colours (lighter toward the tips, a little variation per strand) and a
# header thickness of 60 um, in centimetres as many downloaded files are
python3 - <<'EOF'
import struct
import numpy as np
data = open("wavy.hair", "rb").read()
strands, points, flags, dseg = struct.unpack_from("<4I", data, 4)
at = 128
segs = np.full(strands, dseg, dtype=np.int64)
if flags & 1:
    segs = np.frombuffer(data, "<u2", strands, at).astype(np.int64)
    at += 2 * strands
pts = np.frombuffer(data, "<f4", 3 * points, at).reshape(-1, 3) * 100.0  # metres -> cm
rng = np.random.default_rng(5)
t = np.concatenate([np.linspace(0.0, 1.0, s + 1) for s in segs])
var = np.repeat(rng.uniform(0.85, 1.1, strands), segs + 1)
root = np.array([0.2, 0.12, 0.055]); tip = np.array([0.55, 0.4, 0.2])
col = np.clip((root + (tip - root) * t[:, None]) * var[:, None], 0, 1).astype("<f4")
head = bytearray(data[:128])
struct.pack_into("<I", head, 12, (flags & 1) | 2 | 16)
struct.pack_into("<f", head, 20, 0.006)  # default thickness, cm
body = (segs.astype("<u2").tobytes() if flags & 1 else b"") + pts.astype("<f4").tobytes() + col.tobytes()
open("blonde.hair", "wb").write(bytes(head) + body)
EOF

light='"lights": [{"type": "directional", "direction": [0.4, 0.8, 0.6], "intensity": 2.6, "shadows": true},
                  {"type": "directional", "direction": [-0.7, 0.2, -0.5], "color": [0.7, 0.8, 1.0], "intensity": 0.8}],
       "ambient": [0.12, 0.12, 0.13], "background": [0.06, 0.06, 0.07]'
render() {  # name, camera azimuth, groom entry
  cat > "$1.json" <<EOF
{"resolution": [400, 300], "camera": {"preset": "close", "azimuth": $2, "elevation": 5}, $light,
 "grooms": [$3]}
EOF
  "$clhair" render "$1.json" -o "$1.png" > "$1.log"
  printf '%-22s strands %s ms\n' "$1" "$(awk '$1 == "strands" {print $2; exit}' "$1.log")"
}
render guides_only 30 '{"strands_file": "guides.tfx", "children": {"count": 0}}'
render follow_default 30 '{"strands_file": "guides.tfx"}'
render follow_16 30 '{"strands_file": "guides.tfx", "children": {"count": 16}}'
render interpolated_16 30 '{"strands_file": "guides.tfx", "children": {"mode": "interpolated", "count": 16}}'
render blonde_file_look 30 '{"strands_file": "blonde.hair", "scale": "auto"}'
render blonde_scene_colour 30 '{"strands_file": "blonde.hair", "scale": "auto", "appearance": {"eumelanin": [1.3, 1.0]}}'
render curly_ply -20 '{"strands_file": "curly.ply", "scale": "auto"}'
render curly_ply_clump -20 '{"strands_file": "curly.ply", "scale": "auto", "children": {"mode": "follow", "count": 2, "radius": 0.002, "clump": 0.8}}'

oiiotool guides_only.png follow_default.png follow_16.png interpolated_16.png \
  blonde_file_look.png blonde_scene_colour.png curly_ply.png curly_ply_clump.png \
  --mosaic:pad=4 4x2 -o "$root/docs/images/groom_files_sheet.png"
echo "wrote $root/docs/images/groom_files_sheet.png"
