#!/usr/bin/env bash
# package_list_test.sh BUILD_DIR — scripts/debian-packages.txt covers every Debian package
# the build touched (scripts/check-packages.sh), and the check does catch a missing one:
# without openimageio-tools (whose /usr/bin/iconvert libopenimageio-dev's CMake config
# names) it must fail and name that package. Exit 77 (skipped) without dpkg/apt.
set -euo pipefail
build="$1"
src=$(cd "$(dirname "$0")/.." && pwd)
files="$build/package-files.txt"
rc=0
"$src/scripts/check-packages.sh" collect "$build" >"$files" || rc=$?
((rc == 0)) || exit "$rc"
"$src/scripts/check-packages.sh" check "$src/scripts/debian-packages.txt" "$files" || exit $?
fake=$(mktemp)
trap 'rm -f "$fake"' EXIT
grep -vx openimageio-tools "$src/scripts/debian-packages.txt" >"$fake"
if out=$("$src/scripts/check-packages.sh" check "$fake" "$files" 2>&1); then
  echo "FAIL: the check passed a list without openimageio-tools"
  exit 1
fi
if ! grep -q "openimageio-tools (owner of /usr/bin/iconvert)" <<<"$out"; then
  echo "FAIL: the check failed without naming openimageio-tools: $out"
  exit 1
fi
echo "package list: complete; a list without openimageio-tools is refused, naming it"
