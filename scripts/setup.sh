#!/bin/sh
# scripts/setup.sh [--test | --fuzz]: installs the Debian 12 packages
# tissuebench needs: with apt-get when run as root, otherwise prints the one
# command to run and fails. --test adds python3-vtk9 (VTK's own readers check
# the ParaView files; ./tissuebench test asks for it); --fuzz adds clang,
# libclang-rt-14-dev (libFuzzer, sanitizers) and libomp-14-dev (OpenMP for
# clang), which only the fuzzing harnesses need (scripts/fuzz.sh, .ci/run).
packages="meson ninja-build pkg-config gcc g++ libsuitesparse-dev libopenblas-dev libfcl-dev
libccd-dev libbullet-dev libcgal-dev libgmp-dev tetgen libtet1.5-dev gnuplot-nox libexpat1-dev
libinih-dev libosmesa6-dev libgl-dev libpng-dev libfreetype-dev fonts-dejavu-core parallel"
case "${1:-}" in
  --test) packages="$packages python3-vtk9" ;;
  --fuzz) packages="$packages clang libclang-rt-14-dev libomp-14-dev" ;;
  "") ;;
  *) echo "usage: scripts/setup.sh [--test | --fuzz]" >&2; exit 2 ;;
esac

missing=""
for p in $packages; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  case "$status" in
    *" installed") ;;
    *) missing="$missing $p" ;;
  esac
done
[ -z "$missing" ] && exit 0

if ! command -v apt-get >/dev/null 2>&1; then
  echo "tissuebench: needs a Debian 12 system with these packages:$missing" >&2
  exit 1
fi
if [ "$(id -u)" -ne 0 ]; then
  echo "tissuebench: missing Debian packages. Run:" >&2
  echo "  sudo apt-get update && sudo apt-get install -y$missing" >&2
  exit 1
fi
echo "tissuebench: installing$missing" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -q >&2 && apt-get install -y -q --no-install-recommends $missing >&2
