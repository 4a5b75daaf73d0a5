#!/usr/bin/env bash
# granpack set-up: install what is missing (Debian 12 packages), build, then
#   bash jobs/setup.sh main   run the main job: a small 3D packing on 2 MPI ranks + its analysis
#   bash jobs/setup.sh test   run the whole test suite (this is what .ci/run calls)
#   bash jobs/setup.sh build  only install and build
# Idempotent and quiet when everything is already there. Build tree: build/ (GRANPACK_BUILD_DIR).
set -euo pipefail
mode=${1:-build}
case "$mode" in main|test|build) ;; *) echo "usage: bash jobs/setup.sh main|test|build" >&2; exit 2;; esac
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${GRANPACK_BUILD_DIR:-$root/build}

# Open MPI refuses to start as root without these; CI and most containers run as root.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# More ranks than cores (e.g. 4 ranks on a 2-core laptop) must not be refused.
export OMPI_MCA_rmaps_base_oversubscribe=1

packages=(
  g++ make cmake pkg-config
  openmpi-bin libopenmpi-dev libhdf5-openmpi-dev
  petsc-dev slepc-dev libmetis-dev
  libopenblas0-pthread   # becomes libblas.so.3: MUMPS factorisations 10-100x faster (docs/stiffness.md)
  libeigen3-dev libfftw3-dev libtoml11-dev libcli11-dev nlohmann-json3-dev libgtest-dev
  python3-numpy python3-scipy python3-h5py python3-matplotlib  # scipy: tests/support/hertz_moduli.py, jobs/tools/refit_ik.py
  clang-format   # tests/cli/format.sh checks the layout of the C++ files
)
# The test suite also opens files in ParaView (tests/cli/paraview.sh, docs/visualisation.md):
# Debian's pvbatch renders through X, hence a virtual X server. About 3 minutes to install
# (140 MB of packages, 800 MB on disk); the test is skipped where they are absent.
if [ "$mode" = test ]; then
  packages+=(paraview python3-paraview xvfb)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "[setup] installing missing Debian packages: ${missing[*]}"
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
    "${missing[@]}" >/dev/null
fi

jobs=$(nproc 2>/dev/null || echo 2)
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
log=$build/build.log
if ! cmake --build "$build" -j "$jobs" >"$log" 2>&1; then
  grep -E -A5 "error|Error" "$log" | head -60 >&2
  echo "[setup] build failed; full log: $log" >&2
  exit 1
fi

case "$mode" in
  build) echo "[setup] built: $build/granpack" ;;
  main)
    out=$root/out/main
    mpirun -np 2 "$build/granpack" run "$root/jobs/decks/main.toml" -o "$out"
    mpirun -np 2 "$build/granpack" analyze "$out/final.h5" --json "$out/analysis.json"
    ;;
  test)
    cd "$build"
    ctest -j "$jobs" --output-on-failure --timeout 900
    ;;
esac
