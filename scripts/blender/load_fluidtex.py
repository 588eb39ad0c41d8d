"""Load a fluidtex output folder into Blender as an animated, textured mesh.

Command line (Blender 3.4):

    blender -b --factory-startup --python-exit-code 1 \
        --python scripts/blender/load_fluidtex.py -- \
        --input OUT [--pattern mesh.####.obj|mesh.####.ply] [--atlas PATTERN]
        [--save FILE.blend] [--check] [--name fluidtex] [--clear-scene]
        [--motion-blur]

    (without -b, Blender opens with the sequence loaded)

Input: the UV meshes fluidtex wrote (its --mesh option), one file per frame,
in one of two forms:

* OBJ (fluidtex's default, OUT/mesh.####.obj): mtllib, usemtl, v, vt, vn,
  faces v/vt[/vn], and the .mtl it names, whose map_Kd is that frame's
  atlas. Faces keep their corners; their vt give the UV map. OBJ carries no
  velocities, so a sequence loaded from OBJ has no motion blur.
* PLY (`fluidtex run ... --mesh OUT/mesh.####.ply`): binary little-endian
  PLY (ASCII and big-endian are read too) with per vertex
  `float x y z nx ny nz u v [vx vy vz]` and `list uchar int vertex_indices`
  triangles. Vertices are already split at UV seams (one vertex per
  (position, uv) pair), so the UV of a corner is its vertex's u v. vx vy vz
  (present when fluidtex's input had velocities) become the mesh's
  "velocity" attribute, which Cycles uses for motion blur (see below). The
  vertex count is kept as in the file (nothing is merged); nx ny nz become
  custom split normals (Auto Smooth on), so the seam splits do not show as
  shading creases. A PLY names no material: the atlas of frame N is found by
  pattern, the first that applies of
    1. --atlas PATTERN (a relative PATTERN is taken from the current folder);
    2. the `atlas=` entry of OUT/job.toml (fluidtex records its --atlas there
       as an absolute path; empty means the default, atlas.####.exr in the
       folder that holds job.toml). A recorded atlas path inside the
       recorded `output=` folder is taken at the same place in OUT as it is
       now, so a moved or copied output folder finds its own atlases;
    3. atlas.####.exr beside the meshes.
  --atlas also overrides the .mtl of OBJ meshes.

Positions are taken as they are (z up, no axis change) in both forms: the
files are read by the small parsers below, not by Blender's importers (the
OBJ importer turns Y-up into Z-up by default). --pattern is relative to
--input and also takes fluidtex's other forms, mesh.%04d.obj and
mesh.$F4.obj. Without --pattern: the `mesh=` entry of OUT/job.toml (taken
relative to the run's output folder, so a moved folder still works) when
frames of it are in OUT, else mesh.####.obj, else mesh.####.ply.

What is built:
* a collection NAME (default "fluidtex") holding an empty NAME (the parent,
  to move the whole sequence) and one object per frame, NAME.####, each with
  its own mesh and material;
* per frame a material NAME.####: Principled BSDF whose Base Color is an
  Image Texture node (the frame's atlas, colour space 'Linear' -- Blender
  3.4's name for linear Rec.709; 'Linear Rec.709' is used where that is the
  name -- extension EXTEND) fed by a UV Map node (UVMap);
* UDIM tiles (an atlas path with the <UDIM> token, as fluidtex writes with
  `--atlas 'OUT/atlas.####.<UDIM>.exr'`): the frame's image is a tiled
  image (source TILED, filepath with <UDIM>) with one tile per file of the
  frame on disk (1001, 1002, ...); the UV mesh's coordinates are in UDIM
  space, so the Image Texture node looks each corner up in its tile;
* PLY with vx vy vz: a POINT / FLOAT_VECTOR attribute "velocity" on each
  mesh, in scene units per second, unchanged from the file;
* visibility keys (hide_viewport and hide_render, constant): an object is
  shown from its frame until the next loaded frame, so exactly one is seen
  on any frame (the first before the sequence, the last after it);
* the scene's frame range is set to the frames found, and its fps to the
  fps of OUT/job.toml when there is one;
* --motion-blur: also switches the scene's motion blur on (Render > Motion
  Blur) with the shutter centred on the frame (Cycles' Position: Center).

Motion blur and the unit of the "velocity" attribute (Blender 3.4.1)
--------------------------------------------------------------------
Cycles blurs a mesh with a "velocity" point attribute by moving each vertex
from P - v*t to P + v*t with t = (shutter / 2) / (fps / fps_base) seconds:
the attribute is read in scene units per SECOND of scene time, in the
object's local space (it is scaled and rotated with the object, like the
positions), and the scene's frame rate (fps / fps_base) and the shutter
(in frames) are the only factors; there is no velocity scale setting for
meshes. fluidtex's vx vy vz are already in scene units per second (from
export_fluid.py or any input with per-second velocities), so they are
stored as they are: no conversion. The objects are parented to the root
empty with identity transforms, so world and local velocities agree and a
transform of the empty applies to the blur as to the positions.

How this was established: a 0.5-unit square with an emission shader, seen
by a 64x64 orthographic camera (16 px per unit, 64 samples, Standard view
transform), was given a constant "velocity" attribute (v, 0, 0) and
rendered with motion blur off and on. The streak length d follows from the
horizontal intensity profile: var(on) - var(off) = d^2 / 12 (a box blurred
by a box). Measured d against v * shutter / (fps / fps_base):
  fps 24, shutter 0.5, v 24:           7.998 px = 0.4999 u  (per second: 0.5;
                                       per frame would be 12)
  fps 12, shutter 0.5, v 24:           0.993 u (1.0)
  fps 24, shutter 1.0, v 24:           0.993 u (1.0)
  fps 24, fps_base 2, shutter 0.5, v 24: 0.993 u (1.0: fps_base enters)
  fps 24, shutter 0.5, v 48:           0.993 u (1.0)
  fps 24, shutter 0.5, v 1:            below the noise (0.02 u predicted)
  object scaled by 2: streak 15.8 px (16); rotated 90 degrees about z: the
  streak turns to y (local space).
  Object > Motion Blur > Deformation off (cycles.use_deform_motion): no blur.
Other findings of that experiment:
* The blur is centred on the frame's mesh whatever the shutter position. The
  visibility keys are evaluated at the shutter's centre, so with Position
  Center (the default; --motion-blur sets it) frame N shows frame N's mesh
  blurred over [N - s/2, N + s/2] -- the other frames' objects do not
  appear. With Position End the centre falls before frame N and the
  previous frame's object is rendered; with Start it is frame N's mesh, but
  blurred about N rather than over [N, N + s].
* Keep Object > Motion Blur and Deformation on (the defaults) for the
  loaded objects.
* On real data (frame 3 of a fluidtex PLY run on export_fluid.py's falling
  sphere, vz = -1.23 m/s, shutter 1 frame at 24 fps: d = 0.051 m = 2.7 px
  at 53 px/m) the vertical variance of the rendered silhouette grew by
  0.56 px^2 with blur on, against d^2/12 = 0.62 predicted.
Velocities are those of the surface at the frame (export_fluid.py: the
velocity that carries the surface to the next frame); the blur is linear.

Why one object per frame rather than one object whose mesh a
frame_change_pre handler swaps: the handler needs a Python text datablock
set to Register, which Blender only runs when "Auto Run Python Scripts" is
allowed (off by default; `blender -b file.blend` renders would show a frozen
first frame unless run with -y), and swapping mesh data from a frame-change
handler while the renderer reads it is unsafe (it needs Render > Lock
Interface). Keyed visibility is plain data: it survives save/reload, works
in every engine, viewport and render farm, and for linked or appended
collections. Its cost -- all frames are in memory and in the outliner --
is the same memory as the handler approach (that keeps every mesh too).
Motion blur from positions at neighbouring frames works with neither (the
topology changes from frame to frame): it needs the velocity attribute,
i.e. the PLY meshes of an input with velocities.

--check prints one line of JSON on stdout: frames loaded, first/last frame,
vertices and faces of the first frame, its image path and whether it
exists (of UDIM tiles: tile 1001), its UDIM tiles (1 for one image) and
the largest UDIM tile its UVs reach, whether UVs are present, the colour space used, the collection,
the mesh format and pattern, whether velocities were loaded (any frame) and
the largest |velocity| of the first frame's attribute (scene units/s; 0.0
without velocities).

--clear-scene removes every object of the current scene first (e.g. the
factory startup's cube, camera and light). Without it nothing existing is
touched; a collection named NAME must not exist yet.

Errors: one line on stderr, exit status 1.
"""

import argparse
import glob
import json
import math
import os
import re
import struct
import sys

import bpy

PROG = "load_fluidtex"


class LoadError(Exception):
    pass


def fail(msg):
    sys.stderr.write("%s: error: %s\n" % (PROG, msg))
    sys.exit(1)


def warn(msg):
    sys.stderr.write("%s: warning: %s\n" % (PROG, msg))


class OneLineParser(argparse.ArgumentParser):
    """argparse, but a usage error is one line on stderr and exit status 1."""

    def error(self, message):
        fail(message)


def hash_pattern(pattern):
    """fluidtex's pattern forms (####, %04d, %d, $F4, $F) as runs of #."""
    pattern = re.sub(r"%0?(\d*)d", lambda m: "#" * int(m.group(1) or 1), pattern)
    return re.sub(r"\$F(\d*)", lambda m: "#" * int(m.group(1) or 1), pattern)


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = OneLineParser(prog="load_fluidtex.py",
                      description="Load a fluidtex output folder as an "
                                  "animated, textured mesh sequence.")
    p.add_argument("--input", required=True, help="fluidtex output folder")
    p.add_argument("--pattern",
                   help="mesh file pattern inside --input, .obj or .ply; #### (or %%04d, "
                        "$F4) is the frame number (default: job.toml's mesh pattern, "
                        "else mesh.####.obj, else mesh.####.ply)")
    p.add_argument("--atlas",
                   help="atlas file pattern (default: job.toml's, else atlas.####.exr "
                        "beside the meshes; OBJ: the .mtl's map_Kd)")
    p.add_argument("--save", help="save the result to this .blend")
    p.add_argument("--check", action="store_true",
                   help="print a one-line JSON summary on stdout")
    p.add_argument("--name", default="fluidtex",
                   help="name of the collection, parent empty and object prefix")
    p.add_argument("--clear-scene", action="store_true",
                   help="remove all objects of the scene first")
    p.add_argument("--motion-blur", action="store_true",
                   help="switch the scene's motion blur on (shutter centred on the frame)")
    a = p.parse_args(argv)
    if a.pattern is not None:
        a.pattern = hash_pattern(a.pattern)
        if "#" not in a.pattern:
            p.error("--pattern must contain #### (or %04d, $F4) for the frame number")
        if os.path.splitext(a.pattern)[1].lower() not in (".obj", ".ply"):
            p.error("--pattern must end in .obj or .ply")
    if a.atlas is not None:
        a.atlas = hash_pattern(a.atlas)
        if "#" not in a.atlas:
            p.error("--atlas must contain #### (or %04d, $F4) for the frame number")
        a.atlas = os.path.abspath(a.atlas)
    return a


# --- Files -------------------------------------------------------------------

def split_pattern(pattern):
    m = re.search(r"#+", pattern)
    head, hashes, tail = pattern[:m.start()], m.group(0), pattern[m.end():]
    if "#" in tail:
        raise LoadError("pattern %s has more than one run of #" % pattern)
    return head, len(hashes), tail


def frame_path(pattern, frame):
    """fluidtex's FramePattern::path: zero padded to the number of #."""
    head, width, tail = split_pattern(pattern)
    num = str(abs(frame)).zfill(width)
    return head + ("-" + num if frame < 0 else num) + tail


def find_frames(folder, pattern):
    head, width, tail = split_pattern(pattern)
    full_head = os.path.join(folder, head)
    rx = re.compile(re.escape(os.path.basename(full_head)) + r"(-?\d{%d,})" % width
                    + re.escape(tail) + r"\Z")
    frames = {}
    for path in glob.glob(glob.escape(full_head) + "*" + glob.escape(tail)):
        mm = rx.match(os.path.basename(path))
        if mm:
            f = int(mm.group(1))
            if f in frames:
                raise LoadError("two files for frame %d: %s and %s" % (f, frames[f], path))
            frames[f] = path
    return [(f, frames[f]) for f in sorted(frames)]


def read_job_toml(folder):
    """Top-level key=value entries of folder/job.toml as strings ({} if none).

    fluidtex writes strings raw between " or ' (no escapes), numbers and
    booleans bare, and its [job] table last."""
    entries = {}
    try:
        fh = open(os.path.join(folder, "job.toml"), "r", encoding="utf-8", errors="replace")
    except OSError:
        return entries
    with fh:
        for line in fh:
            s = line.strip()
            if s.startswith("["):
                break
            m = re.match(r"([A-Za-z0-9_-]+)\s*=\s*(.*)\Z", s)
            if not m:
                continue
            value = m.group(2)
            if value[:1] in ("'", '"'):
                end = value.find(value[0], 1)
                value = value[1:end] if end > 0 else value[1:]
            else:
                value = value.split("#", 1)[0].strip()
            entries[m.group(1)] = value
    return entries


def job_fps(job):
    try:
        fps = float(job.get("fps", ""))
        return fps if fps > 0 and math.isfinite(fps) else None
    except ValueError:
        return None


def choose_pattern(folder, job):
    candidates = []
    if job.get("mesh"):
        mesh = os.path.normpath(hash_pattern(job["mesh"]))
        for base in (job.get("output"), folder):  # as recorded, and the folder now
            if base and os.path.isabs(mesh):
                rel = os.path.relpath(mesh, os.path.normpath(base))
                if not rel.startswith(".."):
                    candidates.append(rel)
        candidates.append(os.path.basename(mesh))
    candidates += ["mesh.####.obj", "mesh.####.ply"]
    for c in candidates:
        if "#" not in c or os.path.splitext(c)[1].lower() not in (".obj", ".ply"):
            continue
        if find_frames(folder, c):
            return c
    raise LoadError("no mesh.####.obj or mesh.####.ply in %s (give --pattern)" % folder)


def ply_atlas_pattern(folder, mesh_dir, override, job):
    """The atlas pattern of PLY meshes and where it came from."""
    if override:
        return override, "--atlas"
    if "atlas" in job:
        if not job["atlas"]:
            return os.path.join(folder, "atlas.####.exr"), "job.toml (default)"
        pat = hash_pattern(job["atlas"])
        if not os.path.isabs(pat):
            pat = os.path.join(folder, pat)
        pat = os.path.normpath(pat)
        if job.get("output"):
            # job.toml lies in the run's output folder: an atlas recorded inside
            # it is taken at the same place in the folder as it is now (moved
            # or copied).
            rel = os.path.relpath(pat, os.path.normpath(job["output"]))
            if not rel.startswith(".."):
                return os.path.normpath(os.path.join(folder, rel)), "job.toml"
        return pat, "job.toml"
    return os.path.join(mesh_dir, "atlas.####.exr"), "default"


def parse_obj(path):
    """v, vt and faces (list of (v indices, vt indices or None)); mtllib."""
    verts, uvs, faces = [], [], []
    mtllib = None
    try:
        fh = open(path, "r", encoding="utf-8", errors="replace")
    except OSError as e:
        raise LoadError("cannot read %s: %s" % (path, e.strerror or e))
    with fh:
        for lineno, line in enumerate(fh, 1):
            if not line or line[0] == "#":
                continue
            parts = line.split()
            if not parts:
                continue
            key = parts[0]
            try:
                if key == "v":
                    verts.append((float(parts[1]), float(parts[2]), float(parts[3])))
                elif key == "vt":
                    uvs.append((float(parts[1]), float(parts[2]) if len(parts) > 2 else 0.0))
                elif key == "f":
                    vi, ti = [], []
                    for c in parts[1:]:
                        s = c.split("/")
                        i = int(s[0])
                        vi.append(i - 1 if i > 0 else len(verts) + i)
                        if len(s) > 1 and s[1]:
                            t = int(s[1])
                            ti.append(t - 1 if t > 0 else len(uvs) + t)
                        else:
                            ti.append(None)
                    if len(vi) < 3:
                        raise ValueError("face with %d corners" % len(vi))
                    faces.append((vi, None if None in ti else ti))
                elif key == "mtllib" and mtllib is None:
                    mtllib = line.strip()[len("mtllib"):].strip()
            except (ValueError, IndexError) as e:
                raise LoadError("%s:%d: cannot read %r (%s)" % (path, lineno, line.strip(), e))
    nv, nt = len(verts), len(uvs)
    for vi, ti in faces:
        if min(vi) < 0 or max(vi) >= nv:
            raise LoadError("%s: a face uses vertex %d of %d" % (path, max(vi) + 1, nv))
        if ti is not None and (min(ti) < 0 or max(ti) >= nt):
            raise LoadError("%s: a face uses texture vertex %d of %d" % (path, max(ti) + 1, nt))
    return verts, uvs, faces, mtllib


def atlas_of(obj_path, mtllib):
    """Absolute path of the map_Kd of the .mtl named by mtllib (None if none)."""
    if not mtllib:
        return None
    mtl = os.path.join(os.path.dirname(obj_path), mtllib)
    try:
        with open(mtl, "r", encoding="utf-8", errors="replace") as fh:
            for line in fh:
                s = line.strip()
                if s.startswith("map_Kd"):
                    rest = s[len("map_Kd"):].strip()
                    if rest.startswith("-"):  # options: take the last token
                        rest = rest.split()[-1]
                    return os.path.normpath(os.path.join(os.path.dirname(mtl), rest))
    except OSError as e:
        raise LoadError("cannot read %s (mtllib of %s): %s" % (mtl, obj_path, e.strerror or e))
    return None


PLY_TYPES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B",
             "short": "h", "int16": "h", "ushort": "H", "uint16": "H",
             "int": "i", "int32": "i", "uint": "I", "uint32": "I",
             "float": "f", "float32": "f", "double": "d", "float64": "d"}


def read_ply(path):
    """Elements of a PLY file: {name: (count, props, data)}.

    props: list of (name, type) or (name, 'list', count type, item type).
    data: for an element of scalars, {property: tuple of values}; for an
    element with a list property, {property: list of tuples}.
    """
    try:
        with open(path, "rb") as fh:
            raw = fh.read()
    except OSError as e:
        raise LoadError("cannot read %s: %s" % (path, e.strerror or e))
    if not raw.startswith(b"ply"):
        raise LoadError("%s is not a PLY file" % path)
    end = raw.find(b"end_header")
    if end < 0:
        raise LoadError("%s: no end_header" % path)
    nl = raw.find(b"\n", end)
    body = nl + 1 if nl >= 0 else len(raw)
    fmt, elements = None, []
    for line in raw[:end].decode("ascii", "replace").splitlines()[1:]:
        t = line.split()
        if not t or t[0] in ("comment", "obj_info"):
            continue
        try:
            if t[0] == "format":
                fmt = t[1]
            elif t[0] == "element":
                elements.append([t[1], int(t[2]), []])
            elif t[0] == "property" and t[1] == "list":
                elements[-1][2].append((t[4], "list", PLY_TYPES[t[2]], PLY_TYPES[t[3]]))
            elif t[0] == "property":
                elements[-1][2].append((t[2], PLY_TYPES[t[1]]))
        except (IndexError, KeyError, ValueError):
            raise LoadError("%s: cannot read header line %r" % (path, line))
    if fmt not in ("ascii", "binary_little_endian", "binary_big_endian"):
        raise LoadError("%s: unknown PLY format %r" % (path, fmt))
    out = {}
    try:
        if fmt == "ascii":
            tokens = raw[body:].split()
            pos = 0
            for name, count, props in elements:
                data = {p[0]: [] for p in props}
                for _ in range(count):
                    for p in props:
                        if p[1] == "list":
                            n = int(tokens[pos])
                            conv = float if p[3] in "fd" else int
                            data[p[0]].append(tuple(conv(x) for x in tokens[pos + 1:pos + 1 + n]))
                            pos += 1 + n
                        else:
                            conv = float if p[1] in "fd" else int
                            data[p[0]].append(conv(tokens[pos]))
                            pos += 1
                out[name] = (count, props, data)
            return out
        e = "<" if fmt == "binary_little_endian" else ">"
        view = memoryview(raw)
        off = body
        for name, count, props in elements:
            if all(p[1] != "list" for p in props):
                rec = struct.Struct(e + "".join(p[1] for p in props))
                size = rec.size * count
                if off + size > len(raw):
                    raise LoadError("%s: file ends inside element %s" % (path, name))
                cols = list(zip(*rec.iter_unpack(view[off:off + size]))) if count else \
                    [() for _ in props]
                out[name] = (count, props, {p[0]: c for p, c in zip(props, cols)})
                off += size
                continue
            data = {p[0]: [] for p in props}
            if len(props) == 1:  # the common triangle list: one record layout
                p = props[0]
                cs, isz = struct.calcsize(p[2]), struct.calcsize(p[3])
                tri = struct.Struct(e + p[2] + 3 * p[3])
                size = tri.size * count
                if (cs == 1 and off + size <= len(raw)
                        and raw[off:off + size:tri.size].count(3) == count):
                    data[p[0]] = [r[1:] for r in tri.iter_unpack(view[off:off + size])]
                    out[name] = (count, props, data)
                    off += size
                    continue
            for _ in range(count):
                for p in props:
                    if p[1] == "list":
                        (n,) = struct.unpack_from(e + p[2], raw, off)
                        off += struct.calcsize(p[2])
                        item = struct.Struct(e + str(n) + p[3])
                        data[p[0]].append(item.unpack_from(raw, off))
                        off += item.size
                    else:
                        (v,) = struct.unpack_from(e + p[1], raw, off)
                        off += struct.calcsize(p[1])
                        data[p[0]].append(v)
            out[name] = (count, props, data)
    except (struct.error, IndexError, ValueError) as ex:
        raise LoadError("%s: truncated or malformed PLY data (%s)" % (path, ex))
    return out


def parse_ply(path):
    """Positions, uvs, normals, velocities (flat lists or None) and faces."""
    el = read_ply(path)
    if "vertex" not in el:
        raise LoadError("%s has no vertex element" % path)
    nv, _, vd = el["vertex"]

    def cols(*names):
        if all(n in vd for n in names):
            return [vd[n] for n in names]
        return None

    co = cols("x", "y", "z")
    if co is None:
        raise LoadError("%s: vertices have no x y z" % path)
    uv = cols("u", "v") or cols("s", "t") or cols("texture_u", "texture_v")
    nrm = cols("nx", "ny", "nz")
    vel = cols("vx", "vy", "vz")
    faces = []
    if "face" in el:
        _, props, fd = el["face"]
        key = next((p[0] for p in props if p[1] == "list"
                    and p[0] in ("vertex_indices", "vertex_index")), None)
        if key is None:
            raise LoadError("%s: faces have no vertex_indices" % path)
        faces = fd[key]
    for f in faces:
        if len(f) < 3:
            raise LoadError("%s: a face with %d corners" % (path, len(f)))
        if min(f) < 0 or max(f) >= nv:
            raise LoadError("%s: a face uses vertex %d of %d" % (path, max(f), nv))

    def flat(c):
        return None if c is None else [x for t in zip(*c) for x in t]

    return nv, flat(co), flat(uv), flat(nrm), flat(vel), faces


# --- Blender data ------------------------------------------------------------

def linear_colorspace():
    names = [e.identifier for e in
             bpy.types.ColorManagedInputColorspaceSettings.bl_rna.properties["name"].enum_items]
    for n in ("Linear", "Linear Rec.709"):
        if n in names:
            return n
    raise LoadError("no linear Rec.709 colour space among %s" % names)


def build_mesh(name, nverts, co, faces, loop_uvs, normals=None, velocity=None):
    """faces: vertex index lists; loop_uvs: flat u v per corner (or None);
    normals, velocity: flat xyz per vertex (or None)."""
    me = bpy.data.meshes.new(name)
    me.vertices.add(nverts)
    me.vertices.foreach_set("co", co)
    starts, totals, lverts = [], [], []
    for vi in faces:
        starts.append(len(lverts))
        totals.append(len(vi))
        lverts.extend(vi)
    me.loops.add(len(lverts))
    me.polygons.add(len(faces))
    me.loops.foreach_set("vertex_index", lverts)
    me.polygons.foreach_set("loop_start", starts)
    me.polygons.foreach_set("loop_total", totals)
    if loop_uvs is not None:
        uv = me.uv_layers.new(name="UVMap")
        uv.data.foreach_set("uv", loop_uvs)
    me.polygons.foreach_set("use_smooth", [True] * len(faces))
    me.update()
    if me.validate(clean_customdata=False):
        warn("mesh %s had invalid geometry; Blender cleaned it" % name)
    if len(me.vertices) != nverts:
        raise LoadError("mesh %s: %d vertices after validation, %d read"
                        % (name, len(me.vertices), nverts))
    if velocity is not None:
        attr = me.attributes.new("velocity", 'FLOAT_VECTOR', 'POINT')
        attr.data.foreach_set("vector", velocity)
    if normals is not None and any(normals):
        me.use_auto_smooth = True
        me.auto_smooth_angle = math.pi
        me.normals_split_custom_set_from_vertices(
            [tuple(normals[3 * i:3 * i + 3]) for i in range(nverts)])
    return me


def load_obj_frame(path, name, atlas_override, frame):
    verts, uvs, faces, mtllib = parse_obj(path)
    has_uv = bool(faces) and all(ti is not None for _, ti in faces)
    loop_uvs = [c for _, ti in faces for t in ti for c in uvs[t]] if has_uv else None
    me = build_mesh(name, len(verts), [c for v in verts for c in v],
                    [vi for vi, _ in faces], loop_uvs)
    if atlas_override:
        image = frame_path(atlas_override, frame)
    else:
        image = atlas_of(path, mtllib)
        if image is None:
            warn("%s names no atlas (mtllib/map_Kd); its material has no image" % path)
    if not has_uv and faces:
        warn("%s: faces without vt; no UVs" % path)
    return me, image, has_uv, False


def load_ply_frame(path, name, atlas_pattern, frame):
    nv, co, uv, nrm, vel, faces = parse_ply(path)
    loop_uvs = None
    if uv is not None:
        loop_uvs = [uv[2 * i + k] for f in faces for i in f for k in (0, 1)]
    elif faces:
        warn("%s: vertices without u v; no UVs" % path)
    me = build_mesh(name, nv, co, faces, loop_uvs, nrm, vel)
    return me, frame_path(atlas_pattern, frame), loop_uvs is not None, vel is not None


UDIM_TOKEN = "<UDIM>"


def first_file(image_path):
    """The file an atlas path names: itself, or of UDIM tiles tile 1001."""
    return image_path.replace(UDIM_TOKEN, "1001") if image_path else image_path


def udim_tiles(image_path):
    """UDIM numbers of the tiles of an atlas path with <UDIM> on disk, ascending."""
    head, tail = image_path.split(UDIM_TOKEN, 1)
    tiles = []
    for path in glob.glob(glob.escape(head) + "[1-9][0-9][0-9][0-9]" + glob.escape(tail)):
        tiles.append(int(path[len(head):len(head) + 4]))
    return sorted(tiles)


def uv_udim_max(me):
    """The largest UDIM tile the mesh's UVs reach (1001 for uv in [0,1]^2)."""
    if not me.uv_layers:
        return 1001
    best = 1001
    for d in me.uv_layers[0].data:
        u, v = d.uv
        best = max(best, 1001 + min(9, max(0, int(math.floor(u)))) + 10 * max(0, int(math.floor(v))))
    return best


def load_image(image_path):
    """The image datablock of an atlas path: tiled for a <UDIM> path (one
    tile per file on disk), a reference for a file not made yet."""
    if UDIM_TOKEN in image_path:
        tiles = udim_tiles(image_path)
        img = bpy.data.images.new(os.path.basename(image_path), 1, 1, float_buffer=True, tiled=True)
        img.source = 'TILED'
        img.filepath = image_path
        for number in tiles:
            if number != 1001:
                img.tiles.new(tile_number=number)
        if tiles:
            img.reload()
        return img
    if os.path.isfile(image_path):
        return bpy.data.images.load(image_path, check_existing=True)
    img = bpy.data.images.new(os.path.basename(image_path), 1, 1, float_buffer=True)
    img.source = 'FILE'
    img.filepath = image_path
    return img


def build_material(name, image_path, colorspace):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    out.location = (400, 0)
    bsdf = nt.nodes.new("ShaderNodeBsdfPrincipled")
    bsdf.location = (100, 0)
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.location = (-300, 0)
    tex.extension = 'EXTEND'
    tex.interpolation = 'Linear'
    uvn = nt.nodes.new("ShaderNodeUVMap")
    uvn.location = (-550, 0)
    uvn.uv_map = "UVMap"
    nt.links.new(uvn.outputs["UV"], tex.inputs["Vector"])
    nt.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    if image_path:
        img = load_image(image_path)
        img.colorspace_settings.name = colorspace
        img.alpha_mode = 'NONE'
        tex.image = img
    return mat


def key_visibility(ob, frame, hidden):
    ob.hide_viewport = hidden
    ob.hide_render = hidden
    ob.keyframe_insert("hide_viewport", frame=frame)
    ob.keyframe_insert("hide_render", frame=frame)


def max_velocity(me):
    attr = me.attributes.get("velocity")
    if attr is None or not len(attr.data):
        return 0.0
    flat = [0.0] * (3 * len(attr.data))
    attr.data.foreach_get("vector", flat)
    return max(math.sqrt(flat[i] ** 2 + flat[i + 1] ** 2 + flat[i + 2] ** 2)
               for i in range(0, len(flat), 3))


def load(a):
    folder = os.path.abspath(a.input)
    if not os.path.isdir(folder):
        raise LoadError("%s is not a folder" % folder)
    job = read_job_toml(folder)
    pattern = a.pattern or choose_pattern(folder, job)
    fmt = os.path.splitext(pattern)[1].lower()[1:]
    frames = find_frames(folder, pattern)
    if not frames:
        raise LoadError("no file matches %s" % os.path.join(folder, pattern))
    if a.name in bpy.data.collections:
        raise LoadError("a collection named %r exists already (give --name)" % a.name)
    colorspace = linear_colorspace()
    scene = bpy.context.scene

    atlas_pattern, atlas_from = a.atlas, ("--atlas" if a.atlas else "mtl")
    if fmt == "ply":
        mesh_dir = os.path.dirname(os.path.join(folder, pattern))
        atlas_pattern, atlas_from = ply_atlas_pattern(folder, mesh_dir, a.atlas, job)
        sys.stderr.write("%s: %s frames of %s, atlas %s (%s)\n"
                         % (PROG, len(frames), os.path.join(folder, pattern),
                            atlas_pattern, atlas_from))

    if a.clear_scene:
        for ob in list(scene.objects):
            bpy.data.objects.remove(ob, do_unlink=True)

    coll = bpy.data.collections.new(a.name)
    scene.collection.children.link(coll)
    root = bpy.data.objects.new(a.name, None)
    root.empty_display_size = 0.1
    coll.objects.link(root)

    summary = None
    objects = []
    with_velocity = 0
    missing_atlas = []
    for f, path in frames:
        name = "%s.%04d" % (a.name, f)
        if fmt == "ply":
            me, image, has_uv, has_vel = load_ply_frame(path, name, atlas_pattern, f)
        else:
            me, image, has_uv, has_vel = load_obj_frame(path, name, a.atlas, f)
        if not me.polygons:
            warn("%s has no faces" % path)
        if image is not None and not os.path.isfile(first_file(image)):
            missing_atlas.append(first_file(image))  # still referenced: it may be made later
        with_velocity += has_vel
        me.materials.append(build_material(name, image, colorspace))
        ob = bpy.data.objects.new(name, me)
        coll.objects.link(ob)
        ob.parent = root
        objects.append((f, ob))
        if summary is None:
            summary = {"vertices_first": len(me.vertices), "faces_first": len(me.polygons),
                       "image_first": image,
                       "image_first_exists": bool(image and os.path.isfile(first_file(image))),
                       "image_tiles_first": len(udim_tiles(image)) if image and UDIM_TOKEN in image else 1,
                       "uv_udim_max_first": uv_udim_max(me),
                       "uvs": has_uv, "velocity_max_first": max_velocity(me)}
    if missing_atlas:
        warn("%d atlas files do not exist (first: %s)" % (len(missing_atlas), missing_atlas[0]))
    if fmt == "ply" and 0 < with_velocity < len(frames):
        warn("only %d of %d frames have vx vy vz; the others are not motion blurred"
             % (with_velocity, len(frames)))

    # Visibility: object i is shown on [f_i, f_{i+1}).
    first, last = frames[0][0], frames[-1][0]
    for i, (f, ob) in enumerate(objects):
        if i > 0:
            key_visibility(ob, first, True)
        key_visibility(ob, f, False)
        if i + 1 < len(objects):
            key_visibility(ob, objects[i + 1][0], True)
        ad = ob.animation_data
        if ad and ad.action:
            for fc in ad.action.fcurves:
                for kp in fc.keyframe_points:
                    kp.interpolation = 'CONSTANT'

    scene.frame_start = first
    scene.frame_end = last
    fps = job_fps(job)
    if fps:
        if abs(fps - round(fps)) < 1e-6:
            scene.render.fps, scene.render.fps_base = int(round(fps)), 1.0
        else:
            n = int(fps) + 1
            scene.render.fps, scene.render.fps_base = n, n / fps
    if a.motion_blur:
        scene.render.use_motion_blur = True
        if hasattr(scene, "cycles"):
            scene.cycles.motion_blur_position = 'CENTER'
        if not with_velocity:
            warn("motion blur is on, but no frame has velocities (PLY with vx vy vz)")
    scene.frame_set(first)

    if a.save:
        out = os.path.abspath(a.save)
        try:
            os.makedirs(os.path.dirname(out), exist_ok=True)
            bpy.ops.wm.save_as_mainfile(filepath=out, check_existing=False)
        except (OSError, RuntimeError) as e:
            raise LoadError("cannot save %s: %s" % (out, str(e).strip().splitlines()[-1]))
        sys.stderr.write("%s: saved %s\n" % (PROG, out))

    if a.check:
        summary.update({"frames": len(objects), "first_frame": first, "last_frame": last,
                        "colorspace": colorspace, "collection": coll.name, "format": fmt,
                        "mesh_pattern": os.path.join(folder, pattern),
                        "velocities": with_velocity > 0})
        order = ["frames", "first_frame", "last_frame", "vertices_first", "faces_first",
                 "image_first", "image_first_exists", "image_tiles_first", "uv_udim_max_first",
                 "uvs", "colorspace", "collection",
                 "format", "mesh_pattern", "velocities", "velocity_max_first"]
        print(json.dumps({k: summary[k] for k in order}))
        sys.stdout.flush()


def main():
    a = parse_args()
    try:
        load(a)
    except LoadError as e:
        fail(str(e))


if __name__ == "__main__":
    main()
