#!/bin/sh
# Regenerates docs/QUALITY.md and docs/img/quality/: builds hullmap (Release) in BUILD_DIR, then runs
# bench/quality.py, which generates the scenes, runs hullmap and its peers on them, scores all three
# with `hullmap evaluate`, builds the real maps before and after, and writes the document.
#
#   bench/run_quality.sh [BUILD_DIR]        (default: build-quality)
#   ./setup.sh quality                      installs what it needs first, then runs it
#
# Needs /usr/bin/python3 with numpy, scipy and open3d (Debian: python3-numpy python3-scipy
# python3-open3d), and the real maps in ../shared/data/real (HULLMAP_REAL_DATA_DIR moves them; a
# missing map is left out of the document). HULLMAP_BUILD_ARGS and HULLMAP_REAL_AFTER_ARGS change
# hullmap's command lines (bench/quality.py says how). Takes about 10 minutes on 2 cores.
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build-quality}

launcher=""
if command -v ccache >/dev/null 2>&1; then launcher=-DCMAKE_CXX_COMPILER_LAUNCHER=ccache; fi
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DHULLMAP_BUILD_TESTS=OFF $launcher >/dev/null
cmake --build "$build" -j"$(nproc)" --target hullmap >/dev/null
/usr/bin/python3 "$root/bench/quality.py" --hullmap "$build/cli/hullmap" --out "$root/docs/QUALITY.md" \
  --img "$root/docs/img/quality"
