#!/usr/bin/env bash
# The renderer's folders include one way (render/src/README.md): a file may
# include headers of its own folder and of folders in lower layers, never of
# a higher one.  Prints every include that runs upwards and fails if any.
set -euo pipefail
src=${1:-$(cd "$(dirname "$0")/../.." && pwd)/render/src}
layers=(sampling scene geometry ddm materials textures sky film photonmaps camera lights world run integrators daylight . annual)
layer_of() {
  local i
  for i in "${!layers[@]}"; do [ "${layers[$i]}" = "$1" ] && { echo "$i"; return; }; done
  echo -1
}
bad=0 checked=0
while IFS= read -r f; do
  rel=${f#"$src"/}
  dir=$(dirname "$rel")
  me=$(layer_of "$dir")
  if [ "$me" -lt 0 ]; then echo "not in a layer: $rel"; bad=1; continue; fi
  while IFS= read -r inc; do
    to=${inc%%/*}
    [ "$to" = vr ] && continue
    them=$(layer_of "$to")
    checked=$((checked + 1))
    if [ "$them" -lt 0 ] || [ "$them" -gt "$me" ]; then
      echo "$rel includes $inc: '$to' is not below '$dir'"
      bad=1
    fi
  done < <(sed -n 's/^#include "\([^"]*\)".*/\1/p' "$f")
done < <(find "$src" -name '*.[ch]' | sort)
echo "$checked includes checked"
[ "$checked" -gt 100 ] || { echo "too few includes found under $src"; exit 1; }
exit $bad
