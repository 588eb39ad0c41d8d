"""Free-fall check of an export_fluid.py PLY sequence (run by blender_roundtrip.sh).

    blender -b --factory-startup --python-exit-code 1 \
        --python tests/dcc/check_free_fall.py -- DIR [--frames 1-5] [--fps 24] [--g 9.81]

DIR holds BASE.####.ply (one BASE) written by export_fluid.py from the scene
of make_liquid_scene.py: a liquid sphere falling freely from rest before it
hits the floor (about frame 8 at 24 fps and resolution 24; frames 1-5 are
well before). For the frames given (default 1-5) it reads the vertices
(binary little-endian float x y z ... vx vy vz) and requires
* every increment of the mean vz from one frame to the next to be within 2 %
  of -g/fps (uniform acceleration by gravity), and
* the positions to move with the velocities: fps times the mean-z change
  from frame f to f+1 within 5 % of the mean vz of frame f (export_fluid.py
  writes the velocity that carries the surface to the next frame).
Prints the numbers and exits 0, or one line on stderr and exits 1.
"""

import glob
import os
import re
import struct
import sys

TYPES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h",
         "ushort": "H", "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I",
         "float": "f", "float32": "f", "double": "d", "float64": "d"}


def die(msg):
    sys.stderr.write("check_free_fall: FAIL: %s\n" % msg)
    sys.exit(1)


def read_vertices(path):
    """(count, {name: tuple}) of the vertex element of a binary LE PLY."""
    with open(path, "rb") as fh:
        raw = fh.read()
    end = raw.find(b"end_header\n")
    if not raw.startswith(b"ply\n") or end < 0:
        die("%s is not a PLY file" % path)
    header = raw[:end].decode("ascii", "replace").splitlines()
    if "format binary_little_endian 1.0" not in header:
        die("%s is not binary little-endian" % path)
    elem, count, props = None, 0, []
    for line in header:
        t = line.split()
        if t and t[0] == "element":
            if elem == "vertex":
                break
            elem, count, props = t[1], int(t[2]), []
        elif t and t[0] == "property" and elem == "vertex":
            if t[1] == "list":
                die("%s: list property in the vertex element" % path)
            props.append((t[2], TYPES[t[1]]))
    if elem != "vertex":
        die("%s: the vertex element must come first" % path)
    rec = struct.Struct("<" + "".join(t for _, t in props))
    body = end + len(b"end_header\n")
    cols = list(zip(*rec.iter_unpack(raw[body:body + rec.size * count])))
    data = {name: col for (name, _), col in zip(props, cols)}
    for name in ("z", "vz"):
        if name not in data:
            die("%s: vertices have no %s" % (path, name))
    return count, data


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if not argv:
        die("usage: check_free_fall.py -- DIR [--frames A-B] [--fps F] [--g G]")
    folder, opts = argv[0], dict(zip(argv[1::2], argv[2::2]))
    try:
        a, b = (int(x) for x in opts.get("--frames", "1-5").split("-"))
        fps, g = float(opts.get("--fps", 24)), float(opts.get("--g", 9.81))
    except ValueError:
        die("bad --frames, --fps or --g")
    if b - a < 2:
        die("need at least three frames")
    first = glob.glob(os.path.join(glob.escape(folder), "*.%04d.ply" % a))
    if len(first) != 1:
        die("expected one *.%04d.ply in %s, found %d" % (a, folder, len(first)))
    base = re.sub(r"\.%04d\.ply\Z" % a, "", first[0])
    mean_z, mean_vz, min_z = [], [], []
    for f in range(a, b + 1):
        path = "%s.%04d.ply" % (base, f)
        if not os.path.isfile(path):
            die("%s is missing" % path)
        n, d = read_vertices(path)
        if n == 0:
            die("%s has no vertices" % path)
        mean_z.append(sum(d["z"]) / n)
        mean_vz.append(sum(d["vz"]) / n)
        min_z.append(min(d["z"]))
    expect = -g / fps
    for i, f in enumerate(range(a, b + 1)):
        print("frame %d: mean z %.5f  min z %.5f  mean vz %.5f" % (f, mean_z[i], min_z[i], mean_vz[i]))
    bad = []
    for i in range(len(mean_vz) - 1):
        dv = mean_vz[i + 1] - mean_vz[i]
        err = abs(dv / expect - 1)
        print("vz increment %d->%d: %.5f (expected %.5f, %.2f %% off)" % (a + i, a + i + 1, dv, expect, 100 * err))
        if err > 0.02:
            bad.append("vz increment %d->%d is %.5f, not %.5f within 2 %%" % (a + i, a + i + 1, dv, expect))
    for i in range(len(mean_z) - 1):
        step = fps * (mean_z[i + 1] - mean_z[i])
        err = abs(step / mean_vz[i] - 1) if mean_vz[i] else float("inf")
        print("fps x mean-z step %d->%d: %.5f vs mean vz %.5f (%.2f %% off)" % (a + i, a + i + 1, step, mean_vz[i], 100 * err))
        if err > 0.05:
            bad.append("fps x mean-z step %d->%d is %.5f, mean vz %.5f (over 5 %%)" % (a + i, a + i + 1, step, mean_vz[i]))
    if bad:
        die("; ".join(bad))
    print("check_free_fall: OK (%d frames, g/fps = %.5f)" % (b - a + 1, -expect))


main()
