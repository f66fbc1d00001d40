#!/usr/bin/env bash
# check-packages.sh — does scripts/debian-packages.txt name every Debian package the build uses?
#
#   scripts/check-packages.sh collect BUILD_DIR > files.txt   files the build actually touches
#   scripts/check-packages.sh check LIST files.txt             fail if one is outside LIST's closure
#
# "collect" configures the source tree again into BUILD_DIR/package-trace with
# `cmake --trace-expand` and keeps every absolute path the configure step named that exists
# (the find modules' results, the imported targets' files — /usr/bin/iconvert among them),
# adds the headers recorded in BUILD_DIR's compiler dependency files, the shared libraries
# of BUILD_DIR's executables (ldd), the OpenCL ICDs and the tools the tests run.
# "check" maps each file to its package (dpkg -S) and fails, naming package and file, when
# that package is neither in LIST nor pulled in by LIST's packages (apt-cache depends
# --recurse without recommends, as dev.sh installs), nor essential/required on every
# Debian system. A machine that already has a package cannot hide its absence this way.
# Exit codes: 0 complete, 1 a package is missing, 77 no dpkg/apt here (nothing to check).
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v dpkg-query >/dev/null || ! command -v apt-cache >/dev/null; then
  echo "check-packages: no dpkg/apt on this machine; nothing to check" >&2
  exit 77
fi

collect() {
  local build="$1" trace_dir="$1/package-trace"
  rm -rf "$trace_dir" && mkdir -p "$trace_dir"
  # not searched: this trace, and what the tests write at run time (PoCL's compiled kernels,
  # thousands of shared objects the build did not make; the program cache; test output)
  local -a skip=(\( -path "$trace_dir" -o -path "$build/pocl-cache" -o -path "$build/clhair-cache"
    -o -path "$build/test-output" \) -prune)
  cmake -S . -B "$trace_dir/build" --trace-expand --trace-redirect="$trace_dir/trace.txt" \
    -DCLHAIR_BUILD_TESTS=ON -DCLHAIR_BUILD_BENCH=ON >/dev/null 2>&1 || {
    echo "check-packages: cmake configure failed (see $trace_dir/trace.txt)" >&2
    exit 1
  }
  {
    grep -oE '/usr/[A-Za-z0-9_+./-]+' "$trace_dir/trace.txt" || true
    # headers the compiler read (make-style dependency files)
    find "$build" "${skip[@]}" -o \( -name '*.d' -o -name compiler_depend.make \) \
      -print0 2>/dev/null | xargs -0 -r cat | grep -oE '/usr/[A-Za-z0-9_+./-]+' || true
    # shared libraries of the built executables
    find "$build" "${skip[@]}" -o -type f -perm -u+x -print 2>/dev/null |
      while read -r exe; do
        head -c 4 "$exe" 2>/dev/null | grep -q ELF || continue
        ldd "$exe" 2>/dev/null | grep -oE '/[A-Za-z0-9_+./-]+\.so[.0-9]*' || true
      done
    # the OpenCL drivers the loader finds, and the tools the tests call
    for icd in /etc/OpenCL/vendors/*.icd; do
      [[ -f "$icd" ]] || continue
      echo "$icd"
      lib=$(head -n1 "$icd")
      [[ "$lib" == /* ]] && echo "$lib" || ldconfig -p | awk -v l="$lib" '$1 == l {print $NF}'
    done
    for tool in cmake make c++ clang-15 clang-format-15 oclgrind clinfo pkg-config; do
      command -v "$tool" || true
    done
  } | sort -u | while read -r f; do [[ -e "$f" && ! -d "$f" ]] && echo "$f"; done
}

# "file<TAB>package" for each file on stdin that a package owns, read from dpkg's file
# lists in one pass (the path as given, without a leading /usr, and both forms of its real
# path: merged-/usr systems list files under either)
owners() {
  local q
  q=$(mktemp)
  while read -r f; do
    local r
    r=$(readlink -f "$f")
    printf '%s\t%s\t%s\t%s\t%s\n' "$f" "$f" "${f#/usr}" "$r" "${r#/usr}"
  done >"$q"
  awk -F'\t' '
    FILENAME ~ /\.list$/ {
      if (FNR == 1) { pkg = FILENAME; sub(/.*\//, "", pkg); sub(/\.list$/, "", pkg); sub(/:.*/, "", pkg) }
      if (!($0 in own)) own[$0] = pkg
      next
    }
    { for (i = 2; i <= 5; ++i) if ($i in own) { print $1 "\t" own[$i]; break } }
  ' /var/lib/dpkg/info/*.list "$q"
  rm -f "$q"
}

check() {
  local list="$1" files="$2"
  local -a listed=()
  while read -r pkg; do
    [[ -z "$pkg" || "$pkg" == \#* ]] && continue
    listed+=("$pkg")
  done <"$list"
  local closure
  closure=$(mktemp)
  trap 'rm -f "$closure"' RETURN
  apt-cache depends --recurse --no-recommends --no-suggests --no-conflicts --no-breaks \
    --no-replaces --no-enhances "${listed[@]}" 2>/dev/null | grep -E '^[A-Za-z0-9]' |
    sed 's/:.*//' >"$closure" || true
  if [[ $(wc -l <"$closure") -lt ${#listed[@]} ]]; then
    echo "check-packages: apt-cache knows none of the listed packages (run apt-get update)" >&2
    exit 77
  fi
  # what every Debian system has before anything is installed
  dpkg-query -W -f='${Package} ${Essential} ${Priority}\n' |
    awk '$2 == "yes" || $3 == "required" {print $1}' >>"$closure"
  printf '%s\n' "${listed[@]}" >>"$closure"
  sort -u -o "$closure" "$closure"

  local missing=0 f pkg
  declare -A seen=()
  while IFS=$'\t' read -r f pkg; do  # files no package owns (built here) are not listed
    [[ -n "${seen[$pkg]:-}" ]] && continue
    seen[$pkg]=1
    if ! grep -qxF "$pkg" "$closure"; then
      echo "check-packages: $pkg (owner of $f) is used by the build but is not in $list nor a dependency of its packages" >&2
      missing=1
    fi
  done < <(owners <"$files")
  if ((missing)); then exit 1; fi
  echo "check-packages: ${#seen[@]} packages used, all covered by $list"
}

case "${1:-}" in
  collect) collect "${2:?build dir}" ;;
  check) check "${2:?package list}" "${3:?file list}" ;;
  *)
    echo "usage: scripts/check-packages.sh collect BUILD_DIR | check LIST FILES" >&2
    exit 2
    ;;
esac
