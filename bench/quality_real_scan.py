#!/usr/bin/python3
"""The real-scan sweep: octomap's real laser scan (octomap_scan.dat, 88206 points, sensor at the
origin) thinned as a SLAM map is, built at hullmap's defaults in its own frame, and judged against the
dense scan.

For each seed, fraction and outlier share: a random FRACTION of the scan's points, each moved by
Gaussian noise of NOISE (1 cm) per axis, plus OUTLIERS x that count of points drawn uniformly in the
scan's bounding box, written as XYZ and built with `hullmap build points.xyz -o OUT` (no flag).
Segments at radius R (0.3) near the sensor, in the half it scans (x >= 0): both ends uniform within
NEAR (8 m) of it in (x, y), over scanned ground (the lowest dense point within 1.5 m in (x, y)), at
least R + 0.1 above that ground and at most 2.5 m over it, lengths up to 3 m. Each segment's
distance to the dense scan is sampled every <= 1 cm (distance is 1-Lipschitz, so the true minimum lies
within half a step below the sampled one), and a segment is classed only when that is certain:
  deep   when it comes within R - 0.1 of a dense point (the capsule enters the scanned surface by more
         than 0.1); missed when `hullmap check --json` calls it clear, and unseen (counted apart, as
         `hullmap evaluate` does) when its capsule holds fewer than 3 of the thinned map's points;
  clear  when it keeps R + 0.15 from every dense point; a false alarm when check says it collides.
A false alarm whose first contact is a surface (floor, ceiling, ground) is counted apart as well.

usage: bench/quality_real_scan.py HULLMAP [--scan FILE] [--seeds 1,2,3,4,5] [--fractions 0.05,0.1,0.2]
                                  [--outliers 0.01,0.03,0.05] [--segments 3000] [--extra "build args"]
                                  [--work DIR] [--doc docs/QUALITY.md]
Prints a line per map and the worst case; --doc rewrites that section of docs/QUALITY.md in place."""
import argparse
import json
import os
import shlex
import subprocess
import sys

import numpy as np
from scipy.spatial import cKDTree

RADIUS = 0.3
DEPTH = 0.1
CLEAR = 0.15
NOISE = 0.01
NEAR = 8.0
MAX_LENGTH = 3.0
TOP = 2.5
SEEN = 3


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode not in (0, 1):
        sys.exit(f"{' '.join(cmd)} failed ({r.returncode}): {r.stderr.strip()}")
    return r.stdout


class LocalGround:
    """The lowest dense point within 1.5 m in (x, y) of a place, from a grid of 0.5 m cells."""

    def __init__(self, dense, cell=0.5, reach=3):
        self.cell, self.reach = cell, reach
        self.lo = dense[:, :2].min(axis=0)
        ij = np.floor((dense[:, :2] - self.lo) / cell).astype(int)
        self.z = np.full(ij.max(axis=0) + 1, np.inf)
        np.minimum.at(self.z, (ij[:, 0], ij[:, 1]), dense[:, 2])

    def at(self, x, y):
        i, j = np.floor((np.array([x, y]) - self.lo) / self.cell).astype(int)
        r = self.reach
        block = self.z[max(0, i - r):max(0, i + r + 1), max(0, j - r):max(0, j + r + 1)]
        return block.min() if block.size else np.inf


def draw_segments(rng, count, ground):
    def end_ok(p):
        g = ground.at(p[0], p[1])
        return (p[0] >= 0.0 and np.hypot(p[0], p[1]) <= NEAR and np.isfinite(g) and
                g + RADIUS + 0.1 <= p[2] <= g + TOP)

    out = []
    while len(out) < count:
        a = np.array([rng.uniform(0.0, NEAR), rng.uniform(-NEAR, NEAR), rng.uniform(-1.0, TOP)])
        if not end_ok(a):
            continue
        d = rng.normal(size=3)
        d *= rng.uniform(0.2, MAX_LENGTH) / np.linalg.norm(d)
        b = a + d
        if not end_ok(b):
            continue
        out.append(np.concatenate([a, b]))
    return np.array(out)


def segment_distances(tree, segments, step=0.01):
    """Per segment: the smallest sampled distance to the dense points, and half the sampling step."""
    mins, halves = [], []
    for s in segments:
        a, b = s[:3], s[3:]
        n = max(2, int(np.ceil(np.linalg.norm(b - a) / step)) + 1)
        t = np.linspace(0.0, 1.0, n)[:, None]
        d, _ = tree.query(a + t * (b - a))
        mins.append(d.min())
        halves.append(0.5 * np.linalg.norm(b - a) / (n - 1))
    return np.array(mins), np.array(halves)


def thin(dense, rng, fraction, outliers):
    keep = dense[rng.random(len(dense)) < fraction]
    keep = keep + rng.normal(scale=NOISE, size=keep.shape)
    lo, hi = dense.min(axis=0), dense.max(axis=0)
    extra = rng.uniform(lo, hi, size=(int(round(outliers * len(keep))), 3))
    pts = np.vstack([keep, extra])
    return pts[rng.permutation(len(pts))]


def seen(points, segments, deep, step=0.01):
    """Per segment: whether its capsule of radius R holds at least SEEN map points (deep ones only)."""
    tree = cKDTree(points)
    out = np.zeros(len(segments), dtype=bool)
    for k in np.flatnonzero(deep):
        a, b = segments[k, :3], segments[k, 3:]
        n = max(2, int(np.ceil(np.linalg.norm(b - a) / step)) + 1)
        t = np.linspace(0.0, 1.0, n)[:, None]
        near = set()
        for found in tree.query_ball_point(a + t * (b - a), RADIUS):
            near.update(found)
            if len(near) >= SEEN:
                break
        out[k] = len(near) >= SEEN
    return out


def judge(hullmap, out, segments, segments_path, deep, clear, points):
    lines = run([hullmap, "check", out, "--radius", str(RADIUS), "--segments", segments_path, "--json"]).splitlines()
    verdicts = [json.loads(l) for l in lines if l.startswith("{\"clearance")]
    collides = np.array([v["collides"] for v in verdicts])
    surface = np.array([v["surface"] is not None for v in verdicts])
    fa = clear & collides
    missed = deep & ~collides
    unseen = missed & ~seen(points, segments, missed)
    return {"deep": int(deep.sum()), "missed": int((missed & ~unseen).sum()), "unseen": int(unseen.sum()),
            "clear": int(clear.sum()), "false_alarms": int(fa.sum()), "surface_alarms": int((fa & surface).sum()),
            "fa_share": 100.0 * fa.sum() / max(1, clear.sum()),
            "missed_segments": [int(k) for k in np.flatnonzero(missed & ~unseen)]}


def sweep(hullmap, scan, work, log, seeds=(1, 2, 3, 4, 5), fractions=(0.05, 0.1, 0.2),
          outliers=(0.01, 0.03, 0.05), count=3000, extra=""):
    """The sweep's rows and figures; None when the scan is not there."""
    if not os.path.exists(scan):
        log(f"{scan}: not found; the real-scan sweep is left out")
        return None
    dense = np.loadtxt(scan)
    segments = draw_segments(np.random.default_rng(20261208), count, LocalGround(dense))
    os.makedirs(work, exist_ok=True)
    segments_path = f"{work}/segments.txt"
    np.savetxt(segments_path, segments, fmt="%.6f")
    mins, halves = segment_distances(cKDTree(dense), segments)
    deep = mins < RADIUS - DEPTH
    clear = mins - halves >= RADIUS + CLEAR
    log(f"scan: {len(dense)} points; {count} segments, {deep.sum()} deep, {clear.sum()} clear")
    rows = []
    for seed in seeds:
        for fraction in fractions:
            for share in outliers:
                name = f"s{seed}-f{fraction:g}-o{share:g}"
                points = f"{work}/{name}.xyz"
                rng = np.random.default_rng([seed, int(round(fraction * 1000)), int(round(share * 1000))])
                sample = thin(dense, rng, fraction, share)
                np.savetxt(points, sample, fmt="%.5f")
                out = f"{work}/{name}"
                run([hullmap, "build", points, *shlex.split(extra), "-o", out])
                report = json.load(open(f"{out}/report.json"))
                m = judge(hullmap, out, segments, segments_path, deep, clear, np.loadtxt(points))
                m.update(name=name, seed=seed, fraction=fraction, outliers=share,
                         floor="plane" if (report.get("floor") or {}).get("found") else
                         ("ground" if report.get("ground") else "none"))
                rows.append(m)
                log(f"{name:18s} missed {m['missed']}/{m['deep']} (+{m['unseen']} unseen)  false alarms "
                    f"{m['false_alarms']}/{m['clear']} ({m['fa_share']:.1f}%, {m['surface_alarms']} on a surface)  "
                    f"floor: {m['floor']}")
    worst_missed = max(rows, key=lambda m: m["missed"])
    worst_fa = max(rows, key=lambda m: m["fa_share"])
    summary = (f"**{len(rows)} maps**: deep collisions missed where the map saw them: at most {worst_missed['missed']} "
               f"in a map ({worst_missed['name']}), {sum(m['missed'] for m in rows)} in all "
               f"({sum(m['unseen'] for m in rows)} more unseen); false alarms median "
               f"{np.median([m['fa_share'] for m in rows]):.1f} %, worst {worst_fa['fa_share']:.1f} % ({worst_fa['name']}).")
    return {"rows": rows, "seeds": seeds, "fractions": fractions, "outliers": outliers, "segments": count,
            "deep": int(deep.sum()), "clear": int(clear.sum()), "summary": summary}


def table(w, rows):
    w("| map | points kept % | outliers % | deep | missed, seen (unseen) | clear | false alarms % | on a surface | floor |")
    w("|---|---|---|---|---|---|---|---|---|")
    for m in rows:
        missed = f"**{m['missed']}**" if m["missed"] else "0"
        w(f"| {m['name']} | {100 * m['fraction']:g} | {100 * m['outliers']:g} | {m['deep']} | {missed} ({m['unseen']}) "
          f"| {m['clear']} | {m['fa_share']:.1f} | {m['surface_alarms']} | {m['floor']} |")


def main():
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    default_scan = os.environ.get("HULLMAP_REAL_DATA_DIR", os.path.join(repo, "..", "shared", "data", "real"))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("hullmap")
    ap.add_argument("--scan", default=os.path.join(default_scan, "octomap_scan.dat"))
    ap.add_argument("--seeds", default="1,2,3,4,5")
    ap.add_argument("--fractions", default="0.05,0.1,0.2")
    ap.add_argument("--outliers", default="0.01,0.03,0.05")
    ap.add_argument("--segments", type=int, default=3000)
    ap.add_argument("--extra", default="", help="more hullmap build arguments")
    ap.add_argument("--work", default="/tmp/hullmap-real-scan")
    ap.add_argument("--doc", help="rewrite the real scan's section of this QUALITY.md")
    a = ap.parse_args()
    if not os.path.exists(a.scan):
        sys.exit(f"{a.scan}: not found (HULLMAP_REAL_DATA_DIR names the real data's folder)")
    scan = sweep(a.hullmap, a.scan, a.work, lambda line: print(line, flush=True),
                 tuple(int(x) for x in a.seeds.split(",")), tuple(float(x) for x in a.fractions.split(",")),
                 tuple(float(x) for x in a.outliers.split(",")), a.segments, a.extra)
    print(scan["summary"].replace("**", ""))
    if a.doc:
        sys.path.insert(0, os.path.join(repo, "bench"))
        import quality as q
        lines = []
        q.real_scan_doc(lines.append, scan)
        replace_section(a.doc, "## A real laser scan", "## Real maps", lines)


def replace_section(doc, heading, before, lines):
    """Puts `lines` in place of the section `heading` of `doc` (up to the next '## '), or before the
    section `before` when it has none."""
    text = open(doc).read()
    start = text.find(heading)
    if start >= 0:
        end = text.find("\n## ", start + len(heading))
        end = len(text) if end < 0 else end + 1
    else:
        start = end = text.find(before)
        if start < 0:
            sys.exit(f"{doc}: no '{before}' section to put '{heading}' before")
    with open(doc + ".tmp", "w") as f:
        f.write(text[:start] + "\n".join(lines) + "\n" + text[end:])
    os.replace(doc + ".tmp", doc)
    print(f"rewrote '{heading}' in {doc}")


if __name__ == "__main__":
    main()
