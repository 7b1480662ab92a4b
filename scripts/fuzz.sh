#!/usr/bin/env bash
# scripts/fuzz.sh [SECONDS] [HARNESS...]: builds the libFuzzer harnesses of
# tests/fuzz (a clang build in build-fuzz/, -Dfuzz=true) and runs each for
# SECONDS (default 300; .ci/run uses 20), all of them when none is named
# (obj off stl tetgen msh vtk vtu sph scene pairs jgt points cases
# shardinfo).
# Corpora are kept in build-fuzz/corpus/HARNESS/; the seeds are rebuilt each
# time in build-fuzz/seeds/HARNESS/ from tests/fuzz/seeds, tests/data,
# scenes/*.ini, tests/fuzz/regressions and meshes made by `tissuebench mesh`
# and `simulate --vtk` (the CLI of $TB_CLI, default build/tissuebench; left
# out with a note when it is not built). A harness fails when it finds a
# crash, a sanitizer report, a leak, a hang or a broken contract
# (tests/fuzz/fuzz_check.c): its report is printed with the input in hex and
# the path where libFuzzer saved it. Harnesses run $TB_FUZZ_JOBS at a time
# (default: the number of cores). Ends with "N passed, N failed"; exits 1
# when any failed.
set -uo pipefail
cd "$(dirname "$0")/.."
root=$PWD
secs=${1:-300}
[ $# -gt 0 ] && shift
case "$secs" in '' | *[!0-9]*)
  echo "usage: scripts/fuzz.sh [SECONDS] [HARNESS...]" >&2
  exit 2 ;;
esac
all="obj off stl tetgen msh vtk vtu sph scene pairs jgt points cases shardinfo"
names=${*:-$all}
for h in $names; do
  case " $all " in *" $h "*) ;; *)
    echo "scripts/fuzz.sh: no harness '$h' (harnesses: $all)" >&2
    exit 2 ;;
  esac
done
bd=${TB_FUZZ_BUILD:-build-fuzz}
cli=${TB_CLI:-build/tissuebench}
jobs=${TB_FUZZ_JOBS:-$(nproc)}

# ---- build ----
sh "$root/scripts/setup.sh" --fuzz || exit 1 # clang and libFuzzer, for the harnesses alone
mkdir -p "$bd"
log="$bd/fuzz-build.log"
if { [ -f "$bd/build.ninja" ] || CC=clang CXX=clang++ meson setup "$bd" -Dfuzz=true >"$log" 2>&1; } &&
   ninja -C "$bd" fuzz >>"$log" 2>&1; then
  :
else
  tail -40 "$log"
  echo "scripts/fuzz.sh: building the harnesses failed (log: $log)"
  echo "0 passed, 1 failed"
  exit 1
fi

# ---- seeds ----
seeds="$bd/seeds"
rm -rf "$seeds"
for h in $all; do mkdir -p "$seeds/$h" "$bd/corpus/$h" "$bd/artifacts/$h"; done
for d in tests/fuzz/seeds/*/; do cp "$d"* "$seeds/$(basename "$d")/"; done
cp tests/data/*.txt "$seeds/pairs/"
cp scenes/*.ini scenes/examples/*.ini "$seeds/scene/" 2>/dev/null
for f in tests/fuzz/regressions/*; do
  [ -f "$f" ] || continue
  h=$(basename "$f"); h=${h%%-*}
  [ -d "$seeds/$h" ] && cp "$f" "$seeds/$h/"
done
if [ -x "$cli" ]; then
  gen="$bd/seeds/gen"
  mkdir -p "$gen"
  {
    "$cli" mesh sphere --set verts=42 --out "$seeds/obj/sphere.obj"
    "$cli" mesh sphere --set verts=12 --out "$seeds/off/sphere.off"
    "$cli" mesh sphere --set verts=12 --out "$seeds/vtk/sphere.vtk"
    "$cli" mesh beam --set nx=2 --set ny=1 --set nz=1 --out "$seeds/vtk/beam.vtk"
    "$cli" mesh beam --set nx=2 --set ny=1 --set nz=1 --out "$gen/beam.node"
    "$cli" mesh beam --set nx=2 --set ny=1 --set nz=1 --out "$gen/beam.obj"
    "$cli" mesh spheres "$seeds/obj/sphere.obj" --count 4 --out "$seeds/sph/sphere.sph"
    "$cli" simulate --model msm --mesh "$gen/beam.node" --fix 0 --steps 1 --vtk "$gen/vtu"
  } >"$gen/log" 2>&1 || echo "scripts/fuzz.sh: some seeds could not be made (log: $gen/log)"
  cp "$gen/beam.obj" "$seeds/obj/" 2>/dev/null
  cp "$gen"/vtu/*.vtu "$seeds/vtu/" 2>/dev/null
  # the TetGen harness splits its input at the lines "#@ele" and "#@face"
  [ -f "$gen/beam.node" ] && { cat "$gen/beam.node"; echo "#@ele"; cat "$gen/beam.ele"
    [ -f "$gen/beam.face" ] && { echo "#@face"; cat "$gen/beam.face"; }; } >"$seeds/tetgen/beam"
else
  echo "scripts/fuzz.sh: $cli not built: no generated seeds (only tests/fuzz/seeds)"
fi

# ---- runs ----
run_one() { # HARNESS: one libFuzzer run, its log in $bd/logs/HARNESS.log
  local h=$1
  "$bd/tests/fuzz/fuzz_$h" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$bd/artifacts/$h/" \
    "$bd/corpus/$h" "$seeds/$h" >"$bd/logs/$h.log" 2>&1
  echo $? >"$bd/logs/$h.rc"
}
mkdir -p "$bd/logs"
# the harnesses' temporary folders (a crashed run leaves its own behind)
rm -rf "$bd/tmp" && mkdir -p "$bd/tmp" && TMPDIR=$(cd "$bd/tmp" && pwd) && export TMPDIR
echo "fuzzing $secs s each, $jobs at a time: $names"
running=0
for h in $names; do
  rm -f "$bd/logs/$h.rc"
  run_one "$h" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then wait -n; running=$((running - 1)); fi
done
wait

passed=0 failed=0
for h in $names; do
  rc=$(cat "$bd/logs/$h.rc" 2>/dev/null || echo 1)
  runs=$(grep -Eo 'stat::number_of_executed_units: *[0-9]+' "$bd/logs/$h.log" | grep -Eo '[0-9]+$')
  if [ "$rc" -eq 0 ]; then
    passed=$((passed + 1))
    echo "PASS fuzz_$h: ${runs:-?} inputs, corpus $(ls "$bd/corpus/$h" | wc -l) files"
    continue
  fi
  failed=$((failed + 1))
  echo "FAIL fuzz_$h (exit $rc): log $bd/logs/$h.log"
  grep -E 'contract broken|ERROR: |SUMMARY: |runtime error|#[0-9]+ 0x' "$bd/logs/$h.log" | head -30 |
    sed 's/^/  /'
  for a in $(grep -Eo "Test unit written to [^ ]+" "$bd/logs/$h.log" | sed 's/Test unit written to //'); do
    echo "  reproducer: $a ($(wc -c <"$a") bytes; add it as tests/fuzz/regressions/$h-NAME), hex:"
    od -An -tx1 -v "$a" | head -32 | sed 's/^/   /'
  done
done
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
