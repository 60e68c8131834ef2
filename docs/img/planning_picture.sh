#!/bin/sh
# Regenerates the guide's planning picture (docs/GUIDE.md), docs/img/planning_room.svg: the sample map maps/simple
# built as in the README's tour, its roadmap at radius 0.2 m in the band 0.8-1.2 m, and two drones crossing
# the room (plan --robots), drawn by hullmap plot --roadmap --path --path.
# Usage: docs/img/planning_picture.sh [HULLMAP_BINARY]     (default: build/cli/hullmap)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
room=$here/../../maps/simple
hullmap=${1:-build/cli/hullmap}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
"$hullmap" build "$room/map_points.txt" --trajectory "$room/KeyFrameTrajectory.txt" --up -y --eps 0.12 --min-pts 5 \
  -o "$tmp/out"
"$hullmap" roadmap "$tmp/out" --radius 0.2 --band 0.8,1.2 -o "$tmp/roadmap.json"
printf '%s\n' '# sx sy sz gx gy gz' '-4.5 -3.5 1 4.5 3.5 1' '4.5 -3.5 1 -4.5 3.5 1' >"$tmp/robots.txt"
"$hullmap" plan "$tmp/out" --robots "$tmp/robots.txt" --radius 0.2 --speed 1 -o "$tmp/paths"
"$hullmap" plot "$tmp/out" --roadmap "$tmp/roadmap.json" --path "$tmp/paths/robot_0.txt" \
  --path "$tmp/paths/robot_1.txt" --radius 0.2 -o "$here/planning_room.svg"
