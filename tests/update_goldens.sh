#!/usr/bin/env bash
# update_goldens.sh — renders every image of tests/golden/ again with the `clhair` CLI, as
# listed in tests/golden/goldens.txt (one image a line: file name, scene relative to the
# source tree, CLI options), and records the device they came from in
# tests/golden/device.txt. Run it through the build (`cmake --build build --target
# update_goldens`), never by hand-copying test output; commit the new images on their own,
# saying why they changed.
#
# usage: update_goldens.sh CLHAIR_BINARY SOURCE_DIR
set -euo pipefail
cli="$1"
src="$2"
dir="$src/tests/golden"
manifest="$dir/goldens.txt"
[[ -x "$cli" ]] || { echo "update_goldens: $cli is not an executable" >&2; exit 1; }
[[ -f "$manifest" ]] || { echo "update_goldens: $manifest is missing" >&2; exit 1; }

device=""
while read -r name scene options; do
  [[ -z "$name" || "$name" == \#* ]] && continue
  # shellcheck disable=SC2086  # the options are words by design
  out=$("$cli" render "$src/$scene" -o "$dir/$name" $options)
  line=$(head -n1 <<<"$out")
  echo "$line"
  # "<path>: WxH on DEVICE (sub-group B), ..." -> "DEVICE (sub-group B)"
  this=$(sed -n 's/^[^:]*: [0-9]*x[0-9]* on \(.*)\), .*/\1/p' <<<"$line")
  if [[ -n "$device" && "$this" != "$device" ]]; then
    echo "update_goldens: $name came from \"$this\", the others from \"$device\"" >&2
    exit 1
  fi
  device="$this"
done <"$manifest"
printf '%s\n' "$device" >"$dir/device.txt"
echo "update_goldens: wrote the images of $manifest on $device; commit them on their own, with the reason"
