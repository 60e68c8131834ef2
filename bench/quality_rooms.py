#!/usr/bin/python3
"""Fast run of docs/QUALITY.md's cluttered rooms' sweep alone (bench/quality.py's rooms_part), for
development: prints one line per room and the worst and median false alarms; about 4 s a room.

usage: bench/quality_rooms.py HULLMAP_BINARY [--seeds 201,202,...] [--wider [--doc docs/QUALITY.md]] [--work DIR]

--wider runs the wider held-out rooms (past the sweep's ranges) instead; with --doc it rewrites their
section of docs/QUALITY.md in place.

The seeds default to the document's (held out); pass others to look at rooms the document does not
score. Scenes and builds go to --work (default: a fresh directory under /tmp)."""
import argparse
import importlib.util
import os
import statistics
import sys
import tempfile

ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("hullmap")
ap.add_argument("--seeds", default=None)
ap.add_argument("--work", default=None)
ap.add_argument("--density", type=float, default=None, help="every room at this density instead")
ap.add_argument("--wider", action="store_true", help="the wider held-out rooms")
ap.add_argument("--doc", default=None, help="with --wider: rewrite their section of this QUALITY.md")
ap.add_argument("--repo", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
a = ap.parse_args()
spec = importlib.util.spec_from_file_location("quality", os.path.join(a.repo, "bench", "quality.py"))
q = importlib.util.module_from_spec(spec)
sys.argv = [sys.argv[0]]
spec.loader.exec_module(q)
seeds = tuple(int(x) for x in a.seeds.split(",")) if a.seeds else (q.ROOM_WIDER if a.wider else q.ROOM_SEEDS)
work = a.work or tempfile.mkdtemp(prefix="hullmap-rooms-")
if a.density:
    q.ROOM_DENSITIES = (a.density,)
rows = q.rooms_part(a.hullmap, work, lambda line: print(line, flush=True), seeds,
                    q.wider_room_params if a.wider else q.room_params)
fa = [r["false_alarms"] for r in rows]
print(f"{len(rows)} rooms: missed worst {max(r['missed'] for r in rows)}; false alarms median {statistics.median(fa):.1f} %, "
      f"worst {max(fa):.1f} % (scratch: {work})")
if a.wider and a.doc:
    sys.path.insert(0, os.path.join(a.repo, "bench"))
    import quality_real_scan as rs  # noqa: E402
    lines = []
    q.wider_rooms_doc(lines.append, rows)
    rs.replace_section(a.doc, "## Wider rooms", "## Streets", lines)
