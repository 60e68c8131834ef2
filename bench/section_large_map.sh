#!/bin/sh
# Prints the "## Large maps" section of docs/BENCHMARKS.md (markdown) to stdout.
#
# usage: bench/section_large_map.sh BUILD_DIR [points]
#
# Generates a scene of `points` map points (default 10,000,000) with `hullmap generate`, then runs
# `hullmap build` on it twice: points only (streamed: read, frame, filters and octree batch by
# batch, never the whole file or all points in memory), and with the keyframe trajectory (free
# space ray-cast; every point is needed at once, so the file is read whole).
# Reports each stage's wall time and the process's peak resident memory at its end (report.json's
# timings_ms and peak_rss_mb), the whole run's wall/CPU time and peak RSS (/usr/bin/time when present,
# else report.json alone), and the machine's swap use before and after.
set -eu

if [ $# -lt 1 ]; then
  echo "usage: $0 BUILD_DIR [points]" >&2
  exit 2
fi
build=$1
points=${2:-10000000}
hullmap="$build/cli/hullmap"
if [ ! -x "$hullmap" ]; then
  echo "$0: $hullmap not found (build the hullmap target)" >&2
  exit 2
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

swap_used() { awk '/^SwapTotal/ {t=$2} /^SwapFree/ {f=$2} END {printf "%d", (t-f)/1024}' /proc/meminfo; }

"$hullmap" generate -o "$work/scene" --points "$points" --obstacles 40 --room 20 --seed 42 >/dev/null
size_mb=$(du -m "$work/scene/map_points.txt" | cut -f1)
swap_before=$(swap_used)

run() {  # name, extra build arguments
  name=$1
  shift
  if [ -x /usr/bin/time ]; then
    /usr/bin/time -f '%e %U %S %M' -o "$work/$name.time" \
      "$hullmap" build "$work/scene/map_points.txt" --up -y "$@" -o "$work/$name" >/dev/null
  else
    start=$(date +%s.%N)
    "$hullmap" build "$work/scene/map_points.txt" --up -y "$@" -o "$work/$name" >/dev/null
    echo "$(echo "$(date +%s.%N) - $start" | bc) - - -" >"$work/$name.time"
  fi
}
run points
run trajectory --trajectory "$work/scene/KeyFrameTrajectory.txt"
swap_after=$(swap_used)

echo "## Large maps"
echo
echo "\`hullmap build\` on a generated scene of $points map points (\`hullmap generate --points $points"
echo "--obstacles 40 --room 20 --seed 42\`, ${size_mb} MB of text), res 0.05, eps 0.1, minPts 10. The points-only"
echo "run streams the file: batches of 65,536 points go through read, frame and filters, octree in turn; each"
echo "of those three times is summed over the batches, and the peak RSS of read and frame_and_filters is the"
echo "one at the end of the stream. The run with the trajectory reads the file whole. Per stage: wall time and"
echo "the process's peak resident memory when the stage ends (from \`report.json\`). Whole run: wall and CPU"
echo "time, peak RSS (\`/usr/bin/time\`). Swap in use: ${swap_before} MB before, ${swap_after} MB after."
echo
/usr/bin/python3 - "$work" <<'PY'
import json, sys
work = sys.argv[1]
rows = []
for name, label in (("points", "points only"), ("trajectory", "with trajectory")):
    report = json.load(open(f"{work}/{name}/report.json"))
    t = open(f"{work}/{name}.time").read().split()
    order = ["read", "frame_and_filters", "octree", "dbscan", "obstacles"]
    stages = [s for s in order if s in report["timings_ms"]]
    if not rows:
        print("| run | " + " | ".join(stages) + " | total s | CPU s | peak RSS MB | points used | voxels | clusters |")
        print("|---|" + "---:|" * (len(stages) + 6))
    cells = [f"{report['timings_ms'][s] / 1000:.2f} s / {report['peak_rss_mb'][s]:.0f} MB" for s in stages]
    cpu = "-" if t[1] == "-" else f"{float(t[1]) + float(t[2]):.1f}"
    rss = f"{report['peak_rss_mb'][stages[-1]]:.0f}" if t[3] == "-" else f"{int(t[3]) / 1024:.0f}"
    rows.append(label)
    print(f"| {label} | " + " | ".join(cells) + f" | {float(t[0]):.1f} | {cpu} | {rss} | "
          f"{report['points']['used']:,} of {report['points']['read']:,} | {report['octree']['occupied_voxels']:,} | "
          f"{report['clusters']['count']} |")
PY
echo
echo "Machine: $(nproc) cores, $(awk '/^MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), load average"
echo "$(cut -d' ' -f1-3 /proc/loadavg) at the end. Regenerate: \`bench/section_large_map.sh BUILD_DIR\`."
