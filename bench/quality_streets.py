#!/usr/bin/python3
"""Fast run of docs/QUALITY.md's streets' sweep alone (bench/quality.py's streets_part): prints one line
per street and the summary; with --doc, rewrites that section of docs/QUALITY.md in place (the rest of
the file as bench/quality.py last wrote it). About 10 s a street.

usage: bench/quality_streets.py HULLMAP_BINARY [--seeds 301,302,...] [--work DIR] [--doc docs/QUALITY.md]

Scenes and builds go to --work (default: a fresh directory under /tmp)."""
import argparse
import os
import sys
import tempfile

ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("hullmap")
ap.add_argument("--seeds", default=None)
ap.add_argument("--work", default=None)
ap.add_argument("--doc", default=None, help="rewrite the streets' section of this QUALITY.md")
ap.add_argument("--repo", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
a = ap.parse_args()
sys.path.insert(0, os.path.join(a.repo, "bench"))
import quality as q  # noqa: E402  (the checkout --repo names)
seeds = tuple(int(x) for x in a.seeds.split(",")) if a.seeds else q.STREET_SEEDS
work = a.work or tempfile.mkdtemp(prefix="hullmap-streets-")
rows = q.streets_part(a.hullmap, work, lambda line: print(line, flush=True), seeds)
print(q.street_summary(rows) + f" (scratch: {work})")
if a.doc:
    lines = []
    q.streets_doc(lines.append, rows)
    text = open(a.doc).read()
    start = text.find("## Streets")
    end = text.find("## Real maps", start if start >= 0 else 0)
    if end < 0:
        sys.exit(f"{a.doc}: no '## Real maps' section to put the streets before")
    if start < 0:
        start = end
    with open(a.doc + ".tmp", "w") as f:
        f.write(text[:start] + "\n".join(lines) + "\n" + text[end:])
    os.replace(a.doc + ".tmp", a.doc)
    print(f"rewrote the streets' section of {a.doc}")
