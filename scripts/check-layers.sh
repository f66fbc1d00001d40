#!/usr/bin/env bash
# check-layers.sh — no host file includes a header from a layer above its own (DESIGN.md,
# "Layers"). Each folder of host/ belongs to one layer; a layer may include its own headers
# and those of the layers it builds on, listed below (the same edges the CMake libraries
# link, CMakeLists.txt "the layers"). The public headers (include/clhair/) are the API every
# layer may name, and so are the layouts host and kernels share (kernels/include/clhair/).
# The public headers name no header outside include/ (a user of the library sees only it),
# and only host/stages/ binds and launches kernels.
# Prints every offending #include as file:line and exits 1 if there is one
# (CTest: Layers.NoHostFileIncludesALayerAbove).
set -euo pipefail
cd "$(dirname "$0")/.."

# the layer of each folder of host/ ("." : the files directly in host/)
declare -A layer_of=(
  [io]=io [animation]=io [metrics]=io
  [codec]=codec
  [cl]=cl
  [stages]=stages [lighting]=stages [graph]=stages
  [groom]=groom
  [frame]=frame
  [passes]=renderer [.]=renderer
  [fit]=fit
  [cli]=cli
)
# the layers each layer builds on (closed: every layer below, not only the next)
declare -A below=(
  [io]=""
  [codec]="io"
  [cl]="io"
  [stages]="cl io"
  [groom]="stages cl io"
  [frame]="groom stages cl io"
  [renderer]="frame groom stages cl io"
  [fit]="groom stages cl io"
  [cli]="renderer fit frame groom stages cl io"
)

bad=0
while IFS= read -r -d '' file; do
  rel=${file#host/}
  folder=$(dirname "$rel")
  folder=${folder%%/*}
  from=${layer_of[$folder]:-}
  if [[ -z "$from" ]]; then
    echo "$file: the folder host/$folder has no layer (add it to scripts/check-layers.sh)"
    bad=1
    continue
  fi
  while IFS=: read -r line inc; do
    # "dir/name.h" names a header of host/dir; a bare "name.h" one of host/ itself, unless
    # it sits beside the including file
    [[ "$inc" == .* ]] && continue  # a path relative to the file (kernels/common/...)
    if [[ "$inc" == */* ]]; then
      target=${inc%%/*}
      [[ -d "host/$target" ]] || continue  # clhair/..., a system or third-party header
    else
      [[ -f "$(dirname "$file")/$inc" ]] && continue
      [[ -f "host/$inc" ]] || continue
      target=.
    fi
    to=${layer_of[$target]:-}
    [[ "$to" == "$from" ]] && continue
    if [[ -z "$to" || " ${below[$from]} " != *" $to "* ]]; then
      echo "$file:$line: layer $from includes \"$inc\" of layer ${to:-?} above it or beside it"
      bad=1
    fi
  done < <(grep -n -oE '^[[:space:]]*#[[:space:]]*include[[:space:]]+"[^"]+"' "$file" |
           sed -E 's/^([0-9]+):.*"([^"]+)"/\1:\2/')
done < <(find host -type f \( -name '*.cpp' -o -name '*.h' \) -print0 | sort -z)

# kernels are bound and launched by the stages only (host/stages/; host/cl/ has the helpers)
while IFS= read -r hit; do
  echo "$hit: a kernel is bound outside host/stages/ (give it a stage)"
  bad=1
done < <(grep -rn --include='*.cpp' --include='*.h' -E 'KernelArgs\(|dispatch(Box)?\(dev' host |
         grep -v -E '^host/(stages|cl)/' || true)

# the public API stands alone: its headers include only each other (and system headers)
while IFS= read -r -d '' file; do
  while IFS=: read -r line inc; do
    if [[ ! -f "include/$inc" ]]; then
      echo "$file:$line: a public header includes \"$inc\", which is not in include/"
      bad=1
    fi
  done < <(grep -n -oE '^[[:space:]]*#[[:space:]]*include[[:space:]]+"[^"]+"' "$file" |
           sed -E 's/^([0-9]+):.*"([^"]+)"/\1:\2/')
done < <(find include -type f -name '*.h' -print0 | sort -z)

if [[ $bad -ne 0 ]]; then
  echo "check-layers.sh: host files include headers of layers above them (DESIGN.md, \"Layers\")"
  exit 1
fi
echo "check-layers.sh: every host include goes down the layers"
