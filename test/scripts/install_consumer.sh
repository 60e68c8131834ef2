#!/usr/bin/env bash
# Installs the build tree into a scratch prefix and builds test/consumer against it with
# find_package(hullmap), as a user of the installed package does; runs it on maps/simple and checks
# that it finds as many obstacles as `hullmap build` does on the same file.
set -euo pipefail
build_dir=$1 source_dir=$2 work=$3 hullmap=$4
rm -rf "$work"
cmake --install "$build_dir" --prefix "$work/prefix" >/dev/null
cmake -S "$source_dir/test/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" \
      -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/consumer" -j2 >/dev/null
points="$source_dir/maps/simple/map_points.txt"
"$work/consumer/consumer" "$points" "$work/consumer_out" | tee "$work/consumer.txt"
"$hullmap" build "$points" --up -y -o "$work/cli_out" >/dev/null
expected=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["obstacles"])' "$work/cli_out/report.json")
got=$(sed -n 's/^\([0-9]*\) obstacles.*/\1/p' "$work/consumer.txt")
if [[ "$got" != "$expected" ]]; then
  echo "consumer found $got obstacles, hullmap build $expected" >&2
  exit 1
fi
cmp "$work/consumer_out/obstacles.json" "$work/cli_out/obstacles.json"
echo "obstacle count $got matches hullmap build; obstacles.json identical"
