#!/bin/sh
# scripts/check-layers.sh STAMP NAME=LIB:BELOW,BELOW ... : the layers' one
# rule at the symbol level (the include paths enforce it for headers; see
# docs/architecture.md). Every function or variable a layer's library uses
# and does not define must be defined by a layer below it, not above: for
# each NAME=LIB, the undefined symbols of LIB that another project library
# defines must come from a library of BELOW. Prints each violation and
# exits 1; on success writes STAMP. Run by the build (meson.build).
set -eu
export LC_ALL=C
stamp=$1
shift
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# every library's defined symbols: "symbol layer" lines
for spec; do
  name=${spec%%=*}
  rest=${spec#*=}
  lib=${rest%%:*}
  # strong definitions only: weak ones are C++ inline and template copies
  nm -g --defined-only "$lib" 2>/dev/null | awk -v n="$name" 'NF == 3 && $2 ~ /^[TDBRC]$/ {print $3, n}'
done | sort -u >"$tmp/defined"
bad=0
for spec; do
  name=${spec%%=*}
  rest=${spec#*=}
  lib=${rest%%:*}
  below=$(printf '%s' "${rest#*:}" | tr ',' ' ')
  nm -u "$lib" 2>/dev/null | awk '{print $NF}' | sort -u >"$tmp/used"
  # symbols this layer uses that some project library defines
  join "$tmp/used" "$tmp/defined" >"$tmp/found" || true
  while read -r sym owner; do
    [ "$owner" = "$name" ] && continue
    ok=0
    for b in $below; do [ "$b" = "$owner" ] && ok=1; done
    # a symbol defined in several layers (an inline copy) is fine if one is allowed
    if [ $ok -eq 0 ] && ! awk -v s="$sym" -v allowed=" $below $name " \
        '$1 == s && index(allowed, " " $2 " ") {f = 1} END {exit !f}' "$tmp/defined"; then
      echo "layers: $name uses $sym, defined in $owner (a layer above or beside it)" >&2
      bad=1
    fi
  done <"$tmp/found"
done
[ $bad -eq 0 ] || exit 1
: >"$stamp"
