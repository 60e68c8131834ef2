#!/usr/bin/python3
"""Writes the seed corpus test/fuzz/corpus/<target>/ (small inputs written here, nothing copied).

Run with Debian's /usr/bin/python3 (liblzf through ctypes for the binary_compressed PCD seeds):
    /usr/bin/python3 test/fuzz/make_corpus.py
"""
import ctypes
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(HERE, "corpus")

POINTS = [(0.0, 0.0, 1.0), (0.1, -0.05, 1.01), (0.2, -0.1, 1.02), (-1.5, 2.25, 3e-3),
          (12.0, -7.5, 0.5), (0.0, 0.0, 0.0)]


def write(target, name, data):
    os.makedirs(os.path.join(CORPUS, target), exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(CORPUS, target, name), "wb") as f:
        f.write(data)


def lzf_compress(raw):
    lzf = ctypes.CDLL("liblzf.so.1")
    out = ctypes.create_string_buffer(len(raw) * 2 + 64)
    n = lzf.lzf_compress(raw, len(raw), out, len(out))
    assert n > 0
    return out.raw[:n]


# ---- text -------------------------------------------------------------------------------------
def text_seeds():
    seeds = {
        "header_spaces.txt": "x y z\n" + "".join("%g %g %g\n" % p for p in POINTS),
        "csv_six_columns.csv": "pos_x, pos_y, pos_z, nx, ny, nz\n" +
                               "".join("%g, %g, %g, 0, 0, 1\n" % p for p in POINTS),
        "comments_crlf.xyz": "# map points\r\n\r\n" + "".join("%.6f\t%.6f\t%.6f\r\n" % p for p in POINTS),
        "non_finite.txt": "1 2 3\nnan 0 0\n4 inf -inf\n+5 -6e-3 7E2\n",
        "exponents.txt": "1e308 -1e308 2.5e-310\n1e999 0 0\n",
        "bad_column_count.txt": "1 2 3\n4 5\n",
    }
    for name, data in seeds.items():
        write("text", name, data)
        write("points", name, data)


# ---- ORB-SLAM rostopic echo ---------------------------------------------------------------------
def marker(ns, mid, mtype, points, action=0, seq=1):
    lines = ["header: ", "  seq: %d" % seq, "  stamp: ", "    secs: 1403636580", "    nsecs: 500000000",
             '  frame_id: "/ORB_SLAM/World"', 'ns: "%s"' % ns, "id: %d" % mid, "type: %d" % mtype,
             "action: %d" % action, "pose: ", "  position: ", "    x: 0.0", "    y: 0.0", "    z: 0.0",
             "  orientation: ", "    x: 0.0", "    y: 0.0", "    z: 0.0", "    w: 1.0", "scale: ",
             "  x: 0.01", "  y: 0.01", "  z: 0.0", "color: ", "  r: 0.0", "  g: 0.0", "  b: 0.0",
             "  a: 1.0", "lifetime: ", "  secs: 0", "  nsecs:         0", "frame_locked: False"]
    if points:
        lines.append("points: ")
        for p in points:
            lines += ["  - ", "    x: %r" % p[0], "    y: %r" % p[1], "    z: %r" % p[2]]
        lines.append("colors: ")
        for _ in points:
            lines += ["  - ", "    r: 0.0", "    g: 0.0", "    b: 0.0", "    a: 1.0"]
    else:
        lines += ["points: []", "colors: []"]
    lines += ['text: \'\'', 'mesh_resource: \'\'', "mesh_use_embedded_materials: False"]
    return "\n".join(lines) + "\n---\n"


def echo_seeds():
    full = (marker("KeyFrames", 1, 5, POINTS[:2]) + marker("MapPoints", 0, 8, POINTS) +
            marker("MapPoints", 6, 8, POINTS[3:5]) + marker("Camera", 3, 5, []))
    seeds = {
        "map.txt": full,
        "cut_off.txt": full + marker("MapPoints", 0, 8, POINTS, seq=2)[:700],
        "delete_all.txt": marker("MapPoints", 0, 8, POINTS) + marker("MapPoints", 0, 8, [], action=3),
        "empty_points.txt": marker("MapPoints", 0, 8, []),
        "inline_item.txt": marker("MapPoints", 0, 8, POINTS[:2]).replace("  - \n    x:", "  - x:"),
    }
    for name, data in seeds.items():
        write("orbslam_echo", name, data)
    write("points", "echo_map.txt", full)


# ---- PCD --------------------------------------------------------------------------------------
def pcd_header(fields, sizes, types, counts, width, height, data):
    return ("# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS %s\nSIZE %s\nTYPE %s\n"
            "COUNT %s\nWIDTH %d\nHEIGHT %d\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\nDATA %s\n" %
            (" ".join(fields), " ".join(map(str, sizes)), " ".join(types), " ".join(map(str, counts)),
             width, height, width * height, data)).encode()


def pcd_seeds():
    pts = POINTS
    seeds = {}
    # ascii x y z rgb
    body = "".join("%g %g %g 4.2108e+06\n" % p for p in pts)
    seeds["ascii_xyzrgb.pcd"] = pcd_header("x y z rgb".split(), [4] * 4, "FFFF", [1] * 4, len(pts), 1,
                                           "ascii") + body.encode()
    # binary: x y z F4 + intensity F4 + label U2 (AoS)
    raw = b"".join(struct.pack("<ffffH", *p, 1.0, 7) for p in pts)
    seeds["binary_xyzi_label.pcd"] = pcd_header("x y z intensity label".split(), [4, 4, 4, 4, 2], "FFFFU",
                                                [1] * 5, len(pts), 1, "binary") + raw
    # binary F8 with a padding field of COUNT 3
    raw = b"".join(struct.pack("<ddd3B", *p, 1, 2, 3) for p in pts)
    seeds["binary_f8_pad.pcd"] = pcd_header("x y z _".split(), [8, 8, 8, 1], "FFFU", [1, 1, 1, 3], len(pts), 1,
                                            "binary") + raw
    # organized 3 x 2 cloud with NaN holes, binary_compressed (SoA, LZF)
    org = [pts[0], (math.nan,) * 3, pts[2], pts[3], (math.nan,) * 3, pts[5]]
    soa = b"".join(struct.pack("<6f", *[p[a] for p in org]) for a in range(3))
    soa += struct.pack("<6f", *[0.5] * 6)  # rgb
    comp = lzf_compress(soa)
    seeds["compressed_organized.pcd"] = (pcd_header("x y z rgb".split(), [4] * 4, "FFFF", [1] * 4, 3, 2,
                                                    "binary_compressed") +
                                         struct.pack("<II", len(comp), len(soa)) + comp)
    # a repetitive cloud so the LZF stream holds back references
    rep = [(0.25 * (i % 4), 0.5, 1.0) for i in range(48)]
    soa = b"".join(struct.pack("<48f", *[p[a] for p in rep]) for a in range(3))
    comp = lzf_compress(soa)
    seeds["compressed_backrefs.pcd"] = (pcd_header("x y z".split(), [4] * 3, "FFF", [1] * 3, 48, 1,
                                                   "binary_compressed") +
                                        struct.pack("<II", len(comp), len(soa)) + comp)
    seeds["empty_ascii.pcd"] = pcd_header("x y z".split(), [4] * 3, "FFF", [1] * 3, 0, 1, "ascii")
    for name, data in seeds.items():
        write("pcd", name, data)
    write("points", "ascii_xyzrgb.pcd", seeds["ascii_xyzrgb.pcd"])
    write("points", "compressed_organized.pcd", seeds["compressed_organized.pcd"])


# ---- PLY --------------------------------------------------------------------------------------
def ply_seeds():
    pts = POINTS
    faces = [(0, 1, 2), (2, 3, 4, 5)]
    head = ("ply\nformat %s 1.0\ncomment written by make_corpus.py\nelement vertex %d\n"
            "property float x\nproperty float y\nproperty float z\nproperty uchar red\n"
            "element face %d\nproperty list uchar int vertex_indices\nend_header\n")
    seeds = {}
    ascii_body = "".join("%g %g %g 200\n" % p for p in pts) + "".join(
        "%d %s\n" % (len(f), " ".join(map(str, f))) for f in faces)
    seeds["ascii_faces.ply"] = (head % ("ascii", len(pts), len(faces))) + ascii_body
    for enc, e in (("binary_little_endian", "<"), ("binary_big_endian", ">")):
        body = b"".join(struct.pack(e + "fffB", *p, 200) for p in pts)
        body += b"".join(struct.pack(e + "B%di" % len(f), len(f), *f) for f in faces)
        seeds[enc + ".ply"] = (head % (enc, len(pts), len(faces))).encode() + body
    # doubles, the vertex element after another element, extra int properties
    head2 = ("ply\nformat binary_little_endian 1.0\nelement camera 1\nproperty int width\n"
             "element vertex %d\nproperty double z\nproperty short s\nproperty double y\nproperty double x\n"
             "end_header\n" % len(pts))
    body = struct.pack("<i", 640) + b"".join(struct.pack("<dhdd", p[2], -3, p[1], p[0]) for p in pts)
    seeds["binary_double_order.ply"] = head2.encode() + body
    seeds["no_vertices.ply"] = "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n" \
                               "property float y\nproperty float z\nend_header\n"
    for name, data in seeds.items():
        write("ply", name, data)
    write("points", "binary_little_endian.ply", seeds["binary_little_endian.ply"])


# ---- TUM ---------------------------------------------------------------------------------------
def tum_seeds():
    write("tum", "seconds.txt", "# timestamp tx ty tz qx qy qz qw\n"
          "1403636579.763556 0 0 0 0 0 0 1\n1403636580.263556 0.1 -0.02 0.3 0.01 0.02 -0.03 0.999\n")
    write("tum", "nanoseconds.txt", "1403636579763555840.000000 0.0 0.0 0.0 0.0 0.0 0.0 1.0\n"
          "1403636580263555840.000000 0.5 0.25 -0.125 0.5 0.5 0.5 0.5\n")
    write("tum", "commas_crlf.csv", "0.0, 1, 2, 3, 0, 0, 0, 2\r\n\r\n1.0,\t1, 2, 3, 1, 0, 0, 0 # end\r\n")


# ---- .bt (octomap binary) -----------------------------------------------------------------------
def bt_file(res, data, size):
    return (b"# Octomap OcTree binary file\n# (feel free to add / change comments, but leave the first "
            b"line as it is!)\nid OcTree\nsize %d\nres %s\ndata\n" % (size, repr(res).encode())) + data


def bt_seeds():
    # A node is two bytes, 2 bits per child (children 0-3 then 4-7): 00 none, 01 occupied leaf,
    # 10 free leaf, 11 inner node (its own two bytes follow, depth first). Bit 2i is the low bit.
    def child_bits(kinds):
        code = {"none": 0, "occ": 2, "free": 1, "inner": 3}  # value of bits (2i, 2i+1) as 2i + 2*(2i+1)
        b = [0, 0]
        for i, k in enumerate(kinds):
            b[i // 4] |= code[k] << (2 * (i % 4))
        return bytes(b)

    # A chain of inner nodes down to depth 16, leaves at the finest resolution.
    chain = b"".join(child_bits(["inner"] + ["none"] * 7) for _ in range(15))
    leaves = child_bits(["occ", "free", "occ", "none", "none", "none", "none", "occ"])
    write("bt", "chain.bt", bt_file(0.1, chain + leaves, 20))
    # Pruned: occupied and free leaves near the root (big voxels), an inner node with leaves.
    root = child_bits(["occ", "free", "none", "inner", "none", "none", "none", "none"])
    inner = child_bits(["occ"] * 8)
    write("bt", "pruned.bt", bt_file(0.05, root + inner, 12))
    write("bt", "empty.bt", bt_file(0.2, b"", 0))
    # .ot (full format, readMap reads it too): per node its float log-odds, then one byte with a
    # bit per existing child, children depth first. Root, an occupied and a free leaf at depth 1.
    nodes = struct.pack("<fB", 0.85, 0x81) + struct.pack("<fB", 0.85, 0) + struct.pack("<fB", -2.0, 0)
    write("bt", "leaves.ot", b"# Octomap OcTree file\n# (feel free to add / change comments, but leave the "
          b"first line as it is!)\n#\nid OcTree\nsize 3\nres 0.1\ndata\n" + nodes)


if __name__ == "__main__":
    text_seeds()
    echo_seeds()
    pcd_seeds()
    ply_seeds()
    tum_seeds()
    bt_seeds()
