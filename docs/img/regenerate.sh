#!/bin/sh
# Regenerates the README's pictures (docs/img/sample_*.svg, sample_top.png) from the sample scene.
# Usage: docs/img/regenerate.sh [HULLMAP_BINARY] [SCENE_DIR]
#   HULLMAP_BINARY  default: build/cli/hullmap
#   SCENE_DIR       a directory with map_points.txt and KeyFrameTrajectory.txt in ORB-SLAM's frame (y down);
#                   default: the scene `hullmap generate` writes with its default seed (42), i.e. maps/simple
# PNG rendering needs rsvg-convert (Debian package librsvg2-bin).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
hullmap=${1:-build/cli/hullmap}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
if [ $# -ge 2 ]; then
  scene=$2
else
  scene=$tmp/scene
  "$hullmap" generate -o "$scene"
fi
"$hullmap" build "$scene/map_points.txt" --trajectory "$scene/KeyFrameTrajectory.txt" --up -y \
  --resolution 0.05 --eps 0.12 --min-pts 5 -o "$tmp/out"
"$hullmap" plot "$tmp/out" --path "$here/sample_path.txt" --radius 0.2 -o "$here/sample_top.svg" --png
"$hullmap" plot "$tmp/out" --side -o "$here/sample_side.svg"
"$hullmap" sweep "$scene/map_points.txt" --up -y --eps 0.05,0.1,0.13,0.3 --min-pts 2,5,10,15,35 \
  --plot "$here/sample_sweep.svg"
