#!/usr/bin/python3
"""Which observed points are outside every hull, and why: per true obstacle of a generated scene,
the observed points (map points within 5 cm of its surface, owned by the nearest surface, as
`hullmap evaluate` counts them for min share) that no hull of a build contains, each with the label of
the voxel it falls in (floor / ceiling band left out of the obstacles, DBSCAN noise, unoccupied, or a
cluster whose parts' hulls miss it).

usage: bench/quality_misses.py OUT SCENE [--all]

OUT is a `hullmap build` output directory (obstacles.json, voxels.csv), SCENE a `hullmap generate`
scene with aligned_points.txt (bench/quality_scan.py writes both; the truth's boxes, cylinders and
unions only, no OBJ mesh). Obstacles whose share is below 98 % list their missed points; --all lists
every missed point. Needs python3-numpy and python3-scipy (Debian)."""
import json
import math
import sys
from collections import Counter

import numpy as np
from scipy.spatial import ConvexHull

SURFACE_MARGIN = 0.05  # evaluate's surface_margin
NAMES = {None: "unoccupied", -1: "noise", -2: "floor band", -3: "ceiling band"}


def box_distance(p, center, size, yaw=0.0):
    d = p - np.asarray(center)
    c, s = math.cos(yaw), math.sin(yaw)
    local = np.stack([c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1], d[:, 2]], 1)
    q = np.abs(local) - 0.5 * np.asarray(size)
    return np.linalg.norm(np.maximum(q, 0), axis=1) + np.minimum(q.max(1), 0)


def cylinder_distance(p, center, size):
    d = p - np.asarray(center)
    q = np.stack([np.hypot(d[:, 0], d[:, 1]) - 0.5 * size[0], np.abs(d[:, 2]) - 0.5 * size[2]], 1)
    return np.linalg.norm(np.maximum(q, 0), axis=1) + np.minimum(q.max(1), 0)


def signed_distance(shape, p):
    """As TruthShape::signedDistance (sim/src/ground_truth.cpp)."""
    if shape["shape"] == "union":
        return np.min([signed_distance(part, p) for part in shape["parts"]], axis=0)
    if shape["shape"] == "box":
        return box_distance(p, shape["center"], shape["size"], shape.get("yaw", 0.0))
    if shape["shape"] == "cylinder":
        return cylinder_distance(p, shape["center"], shape["size"])
    sys.exit(f"unsupported truth shape {shape['shape']!r}")


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out, scene = sys.argv[1], sys.argv[2]
    list_all = "--all" in sys.argv[3:]
    truth = json.load(open(f"{scene}/ground_truth.json"))["obstacles"]
    points = np.loadtxt(f"{scene}/aligned_points.txt", usecols=(0, 1, 2), ndmin=2)
    distances = np.stack([np.abs(signed_distance(o, points)) for o in truth], 1)
    owner = distances.argmin(1)
    observed = distances.min(1) <= SURFACE_MARGIN

    inside = np.zeros(len(points), bool)
    build = json.load(open(f"{out}/obstacles.json"))
    for obstacle in build["obstacles"]:
        for part in obstacle.get("parts", [obstacle]):
            vertices = np.asarray(part["hull"]["vertices"], float)
            try:
                planes = ConvexHull(vertices).equations
            except Exception:  # a flat hull contains no volume
                continue
            inside |= (points @ planes[:, :3].T + planes[:, 3] <= 1e-9).all(1)

    resolution = build["parameters"]["resolution"]
    voxels = {}
    with open(f"{out}/voxels.csv") as f:
        next(f)
        for line in f:
            x, y, z, _, label, _ = line.split(",")
            voxels[tuple(math.floor(float(t) / resolution) for t in (x, y, z))] = int(label)

    def label_of(p):
        return voxels.get(tuple(math.floor(t / resolution) for t in p))

    totals = Counter()
    for s, shape in enumerate(truth):
        mine = np.where(observed & (owner == s))[0]
        missed = [i for i in mine if not inside[i]]
        share = 100.0 * (len(mine) - len(missed)) / len(mine) if len(mine) else float("nan")
        why = Counter(NAMES.get(label_of(points[i]), "clustered") for i in missed)
        kind = shape.get("kind", shape["shape"])
        if kind not in ("floor", "ceiling"):
            totals.update(why)
        print(f"{kind} {s}: {len(mine)} observed, {len(missed)} outside every hull ({share:.1f} %)"
              + (f": {dict(why)}" if missed else ""))
        if kind in ("floor", "ceiling") or not missed or (share >= 98.0 and not list_all):
            continue
        for i in missed:
            label = label_of(points[i])
            key = tuple(math.floor(t / resolution) for t in points[i])
            print(f"    {np.round(points[i], 3).tolist()}  {signed_distance(shape, points[i][None])[0]:+.3f} m from "
                  f"its surface, voxel {key}: {NAMES.get(label, f'cluster {label}')}")
    print(f"missed observed points of obstacles (floor and ceiling left out), by their voxel: {dict(totals)}")


if __name__ == "__main__":
    main()
