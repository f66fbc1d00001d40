#!/usr/bin/env bash
# robustness-cases.sh — runs the hostile-input and fault cases of issue 27 against a clhair
# binary and prints, for each, the command, the exit code, the lines it printed on stderr,
# what it left in the output folder and how long it took. It asserts nothing: it shows what
# clhair does (the tests in tests/test_faults.cpp and tests/test_cli_refusals.cpp assert it).
#
#   scripts/robustness-cases.sh build/clhair [scratch folder]
#
# Needs bash, python3 (to build binary inputs) and, for the full-disk and read-only cases,
# root (a small tmpfs is mounted under the scratch folder and unmounted at the end).
set -u
CLHAIR=$(realpath "${1:?usage: $0 path/to/clhair [scratch]}")
ROOT=$(realpath -m "${2:-/tmp/clhair-robustness-$$}")
SRC=$(cd "$(dirname "$0")/.." && pwd)
rm -rf "$ROOT"
mkdir -p "$ROOT"
cd "$ROOT" || exit 1
export CLHAIR_CACHE_DIR=${CLHAIR_CACHE_DIR:-$ROOT/cache}

MOUNTS=()
cleanup() {
  for m in "${MOUNTS[@]}"; do umount "$m" 2>/dev/null; done
}
trap cleanup EXIT

# case ID TITLE -- COMMAND...: runs COMMAND with a 20 s limit in $ROOT, reports.
case_no=0
run_case() {
  local title=$1
  shift
  case_no=$((case_no + 1))
  local t0 t1 rc lines
  t0=$(date +%s.%N)
  timeout -s KILL 20 "$@" >"$ROOT/last.out" 2>"$ROOT/last.err"
  rc=$?
  t1=$(date +%s.%N)
  lines=$(grep -c '' "$ROOT/last.err")
  printf '\n[%02d] %s\n     $ %s\n     rc %s (%s), %s stderr line(s), %.1f s\n' "$case_no" "$title" \
    "$(printf '%q ' "$@" | sed "s#$ROOT/##g")" "$rc" \
    "$( ((rc == 137)) && echo "killed after 20 s" || echo exit)" "$lines" \
    "$(echo "$t1 - $t0" | bc)"
  sed 's/^/     | /' "$ROOT/last.err" | head -6 | cut -c1-220
}
# lists a folder with sizes (hidden files too)
show() { printf '     %s: %s\n' "$1" "$(cd "$1" && find . -maxdepth 1 -type f -printf '%f(%s) ' | sort)"; }

# ---- inputs ---------------------------------------------------------------------------------
cp "$SRC/assets/grooms/tiny.hairmesh.json" tiny.json
scene() {  # scene NAME EXTRA-JSON-KEYS (a 64x48 view of the tiny groom)
  cat >"$1" <<EOF
{"resolution": [64, 48],
 "camera": {"position": [0.0, 0.03, 0.2], "target": [0.0, 0.025, 0.0], "fov": 35},
 "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5]}],
 "grooms": [{"file": "tiny.json"${3:-}}]${2:-}}
EOF
}
scene ok.json ""
"$CLHAIR" render ok.json -o good.png -q && "$CLHAIR" render ok.json -o good.exr -q
cp good.png good2.png
python3 - <<'EOF'
import struct, zlib
def chunk(t, d): return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
# a 16384 x 16384 RGBA header with one row of data
ihdr = struct.pack(">IIBBBBB", 16384, 16384, 8, 6, 0, 0, 0)
row = b"\0" + b"\x80" * (16384 * 4)
open("huge.png", "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(row)) + chunk(b"IEND", b""))
# damaged copies of a good PNG and EXR: bytes in the middle overwritten
for src, dst in (("good.png", "bad.png"), ("good.exr", "bad.exr")):
    b = bytearray(open(src, "rb").read())
    for i in range(len(b) // 2, min(len(b), len(b) // 2 + 64)): b[i] = 0x5a
    open(dst, "wb").write(b)
# a cyHair file of 4 strands whose coordinates are about 1e-30
pts = [(1e-30 * (s + 1), 1e-30 * k, 0.0) for s in range(4) for k in range(8)]
hdr = b"HAIR" + struct.pack("<IIII", 4, 32, 2, 7) + struct.pack("<ff", 1e-32, 0) + struct.pack("<fff", 0.5, 0.5, 0.5) + b"\0" * 88
open("tiny30.hair", "wb").write(hdr + b"".join(struct.pack("<fff", *p) for p in pts))
EOF
# an environment map 64x32 and damaged ones
python3 - <<'EOF'
import json
g = json.load(open("tiny.json"))
n = g["layer_count"] * g["vertex_count"]
import struct
pos = [v for layer in g["layers"] for v in layer]
pos[0] = 1e30
open("cage30.cage", "wb").write(b"CLHCAGE\0" + struct.pack("<IIII", 1, 1, n, 0) + struct.pack("<%df" % len(pos), *pos))
del g["version"]
json.dump(g, open("noversion.json", "w"))
g = json.load(open("tiny.json")); g["strands"] = 5000000
json.dump(g, open("five_million.json", "w"))
EOF
mkfifo fifo.png fifo.exr
ln -s /dev/zero zero.png
ln -s /dev/zero zero.exr
"$CLHAIR" render ok.json -o env.exr --width 64 --height 32 -q
cp bad.exr env_bad.exr
python3 - <<'EOF'
b = bytearray(open("env.exr", "rb").read())
for i in range(len(b) // 2, min(len(b), len(b) // 2 + 64)): b[i] = 0x5a
open("env_bad.exr", "wb").write(b)
EOF
"$CLHAIR" render ok.json -o env.png --width 64 --height 32 -q
python3 - <<'EOF'
b = bytearray(open("env.png", "rb").read())
for i in range(len(b) // 2, min(len(b), len(b) // 2 + 64)): b[i] = 0x5a
open("env_bad.png", "wb").write(b)
EOF

# a full filesystem: a 1 MiB tmpfs filled to the last few KiB
FULL="" RO=""
if [ "$(id -u)" = 0 ]; then
  mkdir -p full ro
  if mount -t tmpfs -o size=1m tmpfs full && mount -t tmpfs -o size=1m tmpfs ro; then
    MOUNTS+=("$ROOT/full" "$ROOT/ro")
    cp good.png ro/existing.png
    mount -o remount,ro "$ROOT/ro"
    cp good.png full/existing.png
    cp good.exr full/existing.exr
    dd if=/dev/zero of=full/filler bs=4k 2>/dev/null
    FULL=$ROOT/full RO=$ROOT/ro
  fi
fi

echo "clhair robustness cases: $CLHAIR in $ROOT"
if [ -n "$FULL" ]; then
  echo "== full disk (a 1 MiB tmpfs with $(stat -f -c '%a' full) free blocks)"
  for ext in png exr jpg; do
    run_case "$ext to a full disk" "$CLHAIR" render ok.json -o "$FULL/out.$ext" -q
    show "$FULL"
  done
  for ext in png exr; do
    run_case "$ext over an existing good file on a full disk" "$CLHAIR" render ok.json -o "$FULL/existing.$ext" -q
    cmp -s "$FULL/existing.$ext" "good.$ext" && echo "     existing.$ext unchanged" || echo "     existing.$ext CHANGED"
    show "$FULL"
  done
  run_case "--frames 1-3 to a full disk" "$CLHAIR" render ok.json --frames 1-3 -o "$FULL/f.####.png" -q
  show "$FULL"
  run_case "compare --error-map to a full disk" "$CLHAIR" compare good.png good2.png --error-map "$FULL/map.png"
  show "$FULL"
  run_case "AOV EXR to a full disk" "$CLHAIR" render ok.json --aov all -o "$FULL/aov.exr" -q
  run_case ".hair to a full disk" "$CLHAIR" export-strands tiny.json -o "$FULL/x.hair"
  run_case ".tfx to a full disk" "$CLHAIR" export-strands tiny.json -o "$FULL/x.tfx"
  run_case "hair mesh to a full disk" "$CLHAIR" groom --preset tiny -o "$FULL/g.json"
  show "$FULL"
  run_case "png to a read-only folder" "$CLHAIR" render ok.json -o "$RO/out.png" -q
  run_case "png over an existing file in a read-only folder" "$CLHAIR" render ok.json -o "$RO/existing.png" -q
  show "$RO"
else
  echo "== full disk and read-only cases skipped (need root to mount a tmpfs)"
fi

echo "== hangs: special files as inputs"
scene bg_fifo.json ', "background_image": "fifo.png"'
run_case "FIFO as background_image" "$CLHAIR" render bg_fifo.json -o o1.png -q
scene bg_zero.json ', "background_image": "zero.png"'
run_case "link to /dev/zero as background_image" "$CLHAIR" render bg_zero.json -o o2.png -q
scene env_fifo.json ', "environment": {"file": "fifo.exr"}'
run_case "FIFO as environment file" "$CLHAIR" render env_fifo.json -o o3.png -q
scene env_zero.json ', "environment": {"file": "zero.exr"}'
run_case "link to /dev/zero as environment file" "$CLHAIR" render env_zero.json -o o4.png -q
run_case "FIFO as compare input" "$CLHAIR" compare fifo.png good.png
run_case "directory as background_image (scene names .)" "$CLHAIR" compare . good.png

echo "== kernel cache"
rm -rf cache_half && mkdir cache_half
CLHAIR_CACHE_DIR=$ROOT/cache_half "$CLHAIR" render ok.json -o c0.png -q
n=0
for f in $(find cache_half -type f); do
  s=$(stat -c %s "$f"); truncate -s $((s / 2)) "$f"; n=$((n + 1))
done
echo "     $n cache entries cut to half their length"
run_case "render with half-length cache entries" env CLHAIR_CACHE_DIR="$ROOT/cache_half" "$CLHAIR" render ok.json -o c1.png -q
run_case "render after that" env CLHAIR_CACHE_DIR="$ROOT/cache_half" "$CLHAIR" render ok.json -o c2.png -q

echo "== one line"
scene bg_bad_png.json ', "background_image": "bad.png"'
run_case "damaged PNG as background" "$CLHAIR" render bg_bad_png.json -o o5.png -q
scene bg_bad_exr.json ', "background_image": "bad.exr"'
run_case "damaged EXR as background" "$CLHAIR" render bg_bad_exr.json -o o6.png -q
scene env_bad_png.json ', "environment": {"file": "env_bad.png"}'
run_case "damaged PNG as environment" "$CLHAIR" render env_bad_png.json -o o7.png -q
scene env_bad_exr.json ', "environment": {"file": "env_bad.exr"}'
run_case "damaged EXR as environment" "$CLHAIR" render env_bad_exr.json -o o8.png -q
for d in 9:9 0:9 no-such-device -1:0; do
  run_case "--device $d" "$CLHAIR" --device "$d" render ok.json -o o9.png -q
done
rm -rf kdir && mkdir -p kdir && cp -r "$SRC/kernels" kdir/
printf '\nthis is not OpenCL C;\n' >>kdir/kernels/shade.cl
run_case "kernel build failure under --kernel-dir" "$CLHAIR" --kernel-dir "$ROOT/kdir" render ok.json -o o10.png -q

echo "== silent acceptance"
run_case "--frames \"\"" "$CLHAIR" render ok.json --frames "" -o "f.####.png" -q
show .
run_case "--frames \"\$SLURM_ARRAY_TASK_ID\" unset" env -u SLURM_ARRAY_TASK_ID bash -c \
  "$CLHAIR render ok.json --frames \"\$SLURM_ARRAY_TASK_ID\" -o s.####.png -q"
scene zero_matrix.json "" ', "transform": {"matrix": [0,0,0,0, 0,0,0,0, 0,0,0,0, 0,0,0,1]}'
run_case "groom matrix of zeros" "$CLHAIR" render zero_matrix.json -o o11.png
cat >tiny30.json <<EOF
{"resolution": [64, 48],
 "camera": {"position": [0.0, 0.03, 0.2], "target": [0.0, 0.025, 0.0], "fov": 35},
 "grooms": [{"strands_file": "tiny30.hair"}]}
EOF
run_case "strand file of coordinates around 1e-30" "$CLHAIR" render tiny30.json -o o12.png
sed 's/"camera": {[^}]*}/"camera": {"preset": "mid"}/' tiny30.json >tiny30_preset.json
run_case "the same, framed by a camera preset" "$CLHAIR" render tiny30_preset.json -o o12b.png
sed 's/"camera": {[^}]*}/"camera": {"preset": "mid"}/' zero_matrix.json >zero_matrix_preset.json
run_case "groom matrix of zeros, framed by a camera preset" "$CLHAIR" render zero_matrix_preset.json -o o11b.png
scene noversion.json "" && sed -i 's/tiny.json/noversion_groom.json/' noversion.json
python3 -c "import json; g=json.load(open('tiny.json')); del g['version']; json.dump(g, open('noversion_groom.json','w'))"
run_case "hair mesh without \"version\"" "$CLHAIR" render noversion.json -o o13.png -q
run_case "groom --strands -5" "$CLHAIR" groom --preset tiny --strands -5 -o neg.json
run_case "export-strands -o x.xyz" "$CLHAIR" export-strands tiny.json -o x.xyz
run_case "unknown subcommand rendr" "$CLHAIR" rendr ok.json -o o14.png
scene cage30.json "" ', "cage_animation": {"file": "cage30.cage"}'
run_case "cage with a coordinate of 1e30" "$CLHAIR" render cage30.json -o o15.png

echo "== valid input refused"
scene five.json "" && sed -i 's/tiny.json/five_million.json/' five.json
run_case "hair mesh asking for 5,000,000 strands" "$CLHAIR" render five.json -o o16.png -q
run_case "-o x.hdr" "$CLHAIR" render ok.json -o x.hdr -q
long=$(printf 'n%.0s' $(seq 250)).png
run_case "254-byte output name" "$CLHAIR" render ok.json -o "$long" -q
ls "$long" >/dev/null 2>&1 && echo "     written" || echo "     not written"

echo "== memory"
scene huge.json ', "background_image": "huge.png"'
run_case "16384^2 PNG header with one data row as background" /usr/bin/time -f "     peak %M KiB" \
  "$CLHAIR" render huge.json -o o17.png -q
