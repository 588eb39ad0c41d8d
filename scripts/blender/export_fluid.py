"""Export a baked Mantaflow liquid surface as a PLY sequence with velocities.

Command line (Blender 3.4, headless):

    blender -b scene.blend --python-exit-code 1 \
        --python scripts/blender/export_fluid.py -- \
        --output DIR [--object NAME] [--frames A-B] [--name BASE]
        [--velocity auto|attribute|grid] [--verbose]

For every frame A..B (default: the scene's frame range) the liquid domain
object (--object, default: the first object whose Fluid modifier is a liquid
domain) is evaluated through the depsgraph; its evaluated mesh is the liquid
surface. It is written to DIR/BASE.####.ply (BASE defaults to the object
name with characters other than [A-Za-z0-9_.-] replaced by '_') as binary
little-endian PLY:

    element vertex N: float x y z vx vy vz   (world space, scene units, /s)
    element face M:   list uchar int vertex_indices   (polygons as they are;
                      Mantaflow's surface is all triangles)

Positions are mapped by the domain's matrix_world, velocities by its 3x3
linear part. Each file is written to NAME.####.ply.tmp, then renamed with
os.replace. A frame whose liquid mesh is empty is skipped with a message on
stderr; the export goes on. Exit status 1 (one line on stderr) when nothing
can be exported or on any error.

Velocities: where they come from and their unit (Blender 3.4.1)
---------------------------------------------------------------
* `FluidDomainSettings.mesh_vertices` (2.8x/2.9x) no longer exists in 3.4.
  With the domain's "Speed Vectors" (use_speed_vectors) on, the evaluated mesh
  has a POINT / FLOAT_VECTOR attribute named "velocity".
* That attribute is only filled when the data cache format is Uni Cache. With
  OpenVDB as data format, Mantaflow tries to save the mesh velocities with the
  data format (lVelMesh_####.vdb), fails without a message, and the attribute
  is all zeros. Then (--velocity auto) this script samples the domain's
  staggered (MAC) velocity grid itself, trilinearly at every vertex, which is
  what Mantaflow does to make the attribute (interpolateMACGrid +
  MdataVec3.setSource(isMAC=True)). The grid is the evaluated domain's
  `velocity_grid` (interleaved xyz, x fastest, res = domain_resolution), with
  the grid placed by `start_point` and `cell_size` (domain-local units).
* Units. Mantaflow works in cells and in its own time unit, 2.5 of which are
  one second of scene time at time scale 1 (frame length 0.1 * 25/fps).
  - grid value g (cells per Mantaflow time unit):
        v = g * (L / R) * 2.5 * time_scale
  - attribute value a (Blender scales g by (1/R) / (0.1 * 25/fps)):
        v = a * 6.25 * time_scale * L / fps
  where v is in scene units per second along the domain's grid axes,
  L = the domain's longest side in world units (Mantaflow's domain size: the
  original mesh's bounding box times the object scale), R =
  resolution_max, fps = scene fps / fps_base. v is then taken to the domain's
  local axes (divided by each axis's scale) and mapped by matrix_world's
  3x3 part. So, for a 1 m domain at 24 fps, attribute values are 3.84 times
  the velocity in m/s, and their ratio to the true velocity changes with the
  domain size and the frame rate.
* How this was established: the test scene of make_liquid_scene.py (a sphere
  falling freely under g = 9.81 in a closed box, resolution 32) was baked
  with Uni Cache data (attribute filled) and with OpenVDB data (attribute
  zero), for a 1 m box at 24 fps, a 2 m box at 24 fps, a 1 m box at 30 fps
  and a 1 m box at time scale 0.5. Before the impact, the mean vz of the
  exported vertices falls by g*ts^2/fps per frame (0.40875 m/s at 24 fps,
  0.327 at 30 fps, 0.1022 at ts 0.5) to within 0.3 %, from both sources, in
  every case; frame f holds vz = -g*ts^2*f/fps (the simulation starts one
  frame before the first frame). Positions agree: fps times each frame's
  mean-z step to the next frame matches that frame's vz (Mantaflow's
  particles advance with the velocity of the frame they leave), so the
  velocities are the ones that carry the surface forward to the next frame.
  The two sources agree to 1e-4 of the speed in the uniform free fall; after
  the impact they differ by 3-15 % RMS (Mantaflow resamples the grid before
  interpolating, and its attribute shows a small mean sideways bias in the
  symmetric splash that the direct samples do not have).
* Frames: outside cache_frame_start..cache_frame_end the modifier passes the
  domain's own box through, and a frame whose mesh file is missing from the
  cache shows the last mesh loaded; both are skipped (message on stderr).
* Scene units: Mantaflow takes the scene gravity (9.81) as Blender units
  per s^2 whatever unit_settings.scale_length is (a bake with scale_length
  0.01 falls exactly like one with 1), so positions and velocities are both
  written in Blender units (metres at unit scale 1), per second of scene time.
"""

import argparse
import array
import glob
import math
import os
import re
import struct
import sys

import bpy

PROG = "export_fluid"


class ExportError(Exception):
    pass


def fail(msg):
    sys.stderr.write("%s: error: %s\n" % (PROG, msg))
    sys.exit(1)


def note(msg):
    sys.stderr.write("%s: %s\n" % (PROG, msg))


class OneLineParser(argparse.ArgumentParser):
    """argparse, but a usage error is one line on stderr and exit status 1."""

    def error(self, message):
        fail(message)


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = OneLineParser(
        prog="export_fluid.py",
        description="Export a baked liquid domain's surface as PLY frames "
                    "with per-vertex velocities (world space, units/s).")
    p.add_argument("--output", required=True, help="output folder")
    p.add_argument("--object", help="liquid domain object (default: the first found)")
    p.add_argument("--frames", help="frame range A-B (default: the scene's range)")
    p.add_argument("--name", help="file base name (default: the object name)")
    p.add_argument("--velocity", choices=("auto", "attribute", "grid"), default="auto",
                   help="velocity source: the mesh's 'velocity' attribute, the "
                        "domain's velocity grid sampled at the vertices, or auto "
                        "(the attribute unless it is missing or all zero)")
    p.add_argument("--verbose", action="store_true",
                   help="print one line per frame (vertices, mean velocity, source)")
    a = p.parse_args(argv)
    if a.frames is not None:
        m = re.fullmatch(r"\s*(-?\d+)\s*(?:-\s*(-?\d+)\s*)?", a.frames)
        if not m:
            p.error("--frames must look like A-B or A")
        first = int(m.group(1))
        last = int(m.group(2)) if m.group(2) is not None else first
        if last < first:
            p.error("--frames: the last frame is before the first")
        a.frames = (first, last)
    return a


def fluid_domain_modifier(ob):
    for md in ob.modifiers:
        if md.type == 'FLUID' and md.fluid_type == 'DOMAIN':
            return md
    return None


def find_domain(name):
    if name is not None:
        ob = bpy.data.objects.get(name)
        if ob is None:
            raise ExportError("no object named %r in %s" % (name, bpy.data.filepath))
        md = fluid_domain_modifier(ob)
        if md is None:
            raise ExportError("object %r has no Fluid domain modifier" % name)
        if md.domain_settings.domain_type != 'LIQUID':
            raise ExportError("object %r is a %s domain, not a liquid one"
                              % (name, md.domain_settings.domain_type.lower()))
        return ob, md
    for ob in bpy.context.scene.objects:
        md = fluid_domain_modifier(ob)
        if md is not None and md.domain_settings.domain_type == 'LIQUID':
            return ob, md
    raise ExportError("the scene has no liquid domain object (give --object)")


def column_norms(m3):
    return [math.sqrt(m3[0][j] ** 2 + m3[1][j] ** 2 + m3[2][j] ** 2) for j in range(3)]


def domain_size(ob):
    """Mantaflow's domain size: longest side of the original mesh's bounding
    box times the object scale, in world units."""
    me = ob.data
    if len(me.vertices) == 0:
        raise ExportError("domain object %r has an empty original mesh" % ob.name)
    co = array.array('f', [0.0]) * (3 * len(me.vertices))
    me.vertices.foreach_get("co", co)
    scale = column_norms(ob.matrix_world.to_3x3())
    ext = [max(co[i::3]) - min(co[i::3]) for i in range(3)]
    return max(e * s for e, s in zip(ext, scale))


def sample_mac(grid, res, start, cell, xs):
    """Trilinear samples of the staggered velocity grid at local positions xs
    (flat xyz); returns flat xyz in Mantaflow units (cells per time unit)."""
    nx, ny, nz = res
    sxy = nx * ny
    n = len(xs) // 3
    out = array.array('f', [0.0]) * (3 * n)
    # Component c lives on the faces normal to axis c: grid coordinates
    # (i, j+0.5, k+0.5) for x, i.e. an offset of 0.5 on the two other axes
    # relative to cell-centre coordinates (cell centres at i + 0.5).
    inv = [1.0 / cell[0], 1.0 / cell[1], 1.0 / cell[2]]
    lim = [nx - 1, ny - 1, nz - 1]
    for c in range(3):
        off = [0.5, 0.5, 0.5]
        off[c] = 0.0
        for v in range(n):
            idx = []
            frac = []
            for a in range(3):
                g = (xs[3 * v + a] - start[a]) * inv[a] - off[a]
                if g < 0.0:
                    g = 0.0
                elif g > lim[a]:
                    g = float(lim[a])
                i = int(g)
                if i >= lim[a]:
                    i = lim[a] - 1 if lim[a] > 0 else 0
                idx.append(i)
                frac.append(g - i)
            i, j, k = idx
            fx, fy, fz = frac
            i1 = i + 1 if nx > 1 else i
            j1 = (j + 1) * nx if ny > 1 else j * nx
            k1 = (k + 1) * sxy if nz > 1 else k * sxy
            j0 = j * nx
            k0 = k * sxy
            g00 = grid[3 * (i + j0 + k0) + c] * (1 - fx) + grid[3 * (i1 + j0 + k0) + c] * fx
            g10 = grid[3 * (i + j1 + k0) + c] * (1 - fx) + grid[3 * (i1 + j1 + k0) + c] * fx
            g01 = grid[3 * (i + j0 + k1) + c] * (1 - fx) + grid[3 * (i1 + j0 + k1) + c] * fx
            g11 = grid[3 * (i + j1 + k1) + c] * (1 - fx) + grid[3 * (i1 + j1 + k1) + c] * fx
            out[3 * v + c] = ((g00 * (1 - fy) + g10 * fy) * (1 - fz)
                              + (g01 * (1 - fy) + g11 * fy) * fz)
    return out


def write_ply(path, pos, vel, loop_totals, loop_verts, comment):
    n = len(pos) // 3
    faces = []
    start = 0
    for cnt in loop_totals:
        idx = loop_verts[start:start + cnt]
        start += cnt
        if cnt <= 255:
            faces.append(idx)
        else:  # a uchar count cannot hold it: fan
            for t in range(1, cnt - 1):
                faces.append([idx[0], idx[t], idx[t + 1]])
    header = ("ply\nformat binary_little_endian 1.0\n"
              "comment %s\n"
              "element vertex %d\n"
              "property float x\nproperty float y\nproperty float z\n"
              "property float vx\nproperty float vy\nproperty float vz\n"
              "element face %d\n"
              "property list uchar int vertex_indices\n"
              "end_header\n" % (comment, n, len(faces)))
    verts = array.array('f', [0.0]) * (6 * n)
    for v in range(n):
        verts[6 * v:6 * v + 3] = pos[3 * v:3 * v + 3]
        verts[6 * v + 3:6 * v + 6] = vel[3 * v:3 * v + 3]
    if sys.byteorder != "little":
        verts.byteswap()
    body = bytearray()
    for f in faces:
        body += struct.pack("<B%di" % len(f), len(f), *f)
    tmp = path + ".tmp"
    try:
        with open(tmp, "wb") as fh:
            fh.write(header.encode("ascii"))
            fh.write(verts.tobytes())
            fh.write(body)
        os.replace(tmp, path)
    except OSError as e:
        try:
            os.remove(tmp)
        except OSError:
            pass
        raise ExportError("cannot write %s: %s" % (path, e.strerror or e))


def export(a):
    scene = bpy.context.scene
    ob, md = find_domain(a.object)
    ds = md.domain_settings
    if ds.cache_type in ('ALL', 'MODULAR') and not ds.has_cache_baked_data:
        raise ExportError("domain %r has no baked data (cache %s)"
                          % (ob.name, bpy.path.abspath(ds.cache_directory)))
    if not ds.use_mesh:
        raise ExportError("domain %r has no liquid mesh (Mesh is off in its settings)" % ob.name)
    first, last = a.frames if a.frames else (scene.frame_start, scene.frame_end)
    base = a.name or re.sub(r"[^A-Za-z0-9_.-]", "_", ob.name)
    out_dir = os.path.abspath(a.output)
    try:
        os.makedirs(out_dir, exist_ok=True)
    except OSError as e:
        raise ExportError("cannot create %s: %s" % (out_dir, e.strerror or e))

    fps = scene.render.fps / scene.render.fps_base
    ts = ds.time_scale
    size = domain_size(ob)
    res_max = ds.resolution_max
    # Scene units per second per stored unit, along the grid axes (see docstring).
    k_attr = 6.25 * ts * size / fps
    k_grid = (size / res_max) * 2.5 * ts
    if scene.unit_settings.scale_length != 1.0:
        note("warning: scene unit scale is %g; positions and velocities are written "
             "in Blender units (the unit Mantaflow takes gravity in)"
             % scene.unit_settings.scale_length)

    # Outside the baked frames the fluid modifier passes the domain's own mesh
    # (the box) through; such frames have no liquid.
    orig_co = array.array('f', [0.0]) * (3 * len(ob.data.vertices))
    ob.data.vertices.foreach_get("co", orig_co)
    cache_first, cache_last = ds.cache_frame_start, ds.cache_frame_end
    # Where a frame's baked mesh is missing (an interrupted or partial bake),
    # Blender silently shows the last mesh it loaded: look for the files.
    cache_dir = bpy.path.abspath(ds.cache_directory)
    mesh_ext = {'BOBJECT': ".bobj.gz", 'OBJECT': ".obj"}.get(ds.cache_mesh_format)
    check_files = (ds.cache_type in ('ALL', 'MODULAR') and ds.cache_frame_offset == 0
                   and mesh_ext is not None and os.path.isdir(os.path.join(cache_dir, "mesh")))

    written = 0
    depsgraph = bpy.context.evaluated_depsgraph_get()
    for frame in range(first, last + 1):
        path = os.path.join(out_dir, "%s.%04d.ply" % (base, frame))
        older = " (an older %s is left as it was)" % path if os.path.exists(path) else ""
        if not cache_first <= frame <= cache_last:
            note("frame %d: outside the domain's cache frames %d-%d; no file written%s"
                 % (frame, cache_first, cache_last, older))
            continue
        if check_files:
            mesh_file = os.path.join(cache_dir, "mesh", "fluid_mesh_%04d%s" % (frame, mesh_ext))
            if not os.path.isfile(mesh_file):
                note("frame %d: no baked liquid mesh (%s is missing); no file written%s"
                     % (frame, mesh_file, older))
                continue
        scene.frame_set(frame)
        ev = ob.evaluated_get(depsgraph)
        me = ev.data
        n = len(me.vertices)
        if n == 0 or len(me.polygons) == 0:
            note("frame %d: the liquid mesh is empty; no file written%s" % (frame, older))
            continue
        co = array.array('f', [0.0]) * (3 * n)
        me.vertices.foreach_get("co", co)
        if co == orig_co:
            note("frame %d: no baked liquid mesh (the domain shows its own mesh); "
                 "no file written%s" % (frame, older))
            continue

        # Velocity source.
        attr = me.attributes.get("velocity")
        if attr is not None and (attr.domain != 'POINT' or attr.data_type != 'FLOAT_VECTOR'):
            attr = None
        raw = None
        source = None
        if a.velocity in ("auto", "attribute"):
            if attr is None:
                if a.velocity == "attribute":
                    raise ExportError("frame %d: the mesh has no 'velocity' point attribute "
                                      "(enable Speed Vectors on the domain and rebake)" % frame)
            else:
                raw = array.array('f', [0.0]) * (3 * n)
                attr.data.foreach_get("vector", raw)
                if a.velocity == "auto" and not any(raw):
                    raw = None
                else:
                    source, k = "attribute", k_attr
        if raw is None:
            if check_files and not glob.glob(os.path.join(glob.escape(cache_dir), "data",
                                                          "*_%04d.*" % frame)):
                raise ExportError("frame %d: no baked data in %s for the velocity grid"
                                  % (frame, os.path.join(cache_dir, "data")))
            eds = fluid_domain_modifier(ev).domain_settings
            res = tuple(eds.domain_resolution)
            grid = eds.velocity_grid[:]
            if len(grid) != 3 * res[0] * res[1] * res[2] or len(grid) == 0:
                raise ExportError("frame %d: the domain's velocity grid is not available "
                                  "(%d values for resolution %s)" % (frame, len(grid), res))
            raw = sample_mac(grid, res, tuple(eds.start_point), tuple(eds.cell_size), co)
            source, k = "grid", k_grid

        m = ev.matrix_world
        m3 = m.to_3x3()
        sc = column_norms(m3)
        # Grid-axis velocity (world units) -> local units -> world.
        lv = [k / s if s > 0 else 0.0 for s in sc]
        r = [[m3[i][j] * lv[j] for j in range(3)] for i in range(3)]
        mm = [[m[i][j] for j in range(4)] for i in range(3)]
        pos = array.array('f', [0.0]) * (3 * n)
        vel = array.array('f', [0.0]) * (3 * n)
        for v in range(n):
            x, y, z = co[3 * v], co[3 * v + 1], co[3 * v + 2]
            ux, uy, uz = raw[3 * v], raw[3 * v + 1], raw[3 * v + 2]
            for i in range(3):
                pos[3 * v + i] = mm[i][0] * x + mm[i][1] * y + mm[i][2] * z + mm[i][3]
                vel[3 * v + i] = r[i][0] * ux + r[i][1] * uy + r[i][2] * uz

        totals = array.array('i', [0]) * len(me.polygons)
        me.polygons.foreach_get("loop_total", totals)
        lverts = array.array('i', [0]) * len(me.loops)
        me.loops.foreach_get("vertex_index", lverts)
        write_ply(path, pos, vel, totals, lverts,
                  "export_fluid.py: Blender %s, object %s, frame %d, fps %g, "
                  "velocity from %s" % (bpy.app.version_string, ob.name, frame, fps, source))
        written += 1
        if a.verbose:
            note("frame %d: %d vertices, %d faces, mean z %.5f, mean v (%.5f %.5f %.5f) "
                 "from %s -> %s" % (frame, n, len(totals), sum(pos[2::3]) / n,
                                    sum(vel[0::3]) / n, sum(vel[1::3]) / n, sum(vel[2::3]) / n,
                                    source, path))
    if written == 0:
        raise ExportError("no frame in %d-%d has a liquid mesh; nothing written" % (first, last))
    note("wrote %d frame(s) of %s to %s" % (written, ob.name, out_dir))


def main():
    a = parse_args()
    try:
        export(a)
    except ExportError as e:
        fail(str(e))


if __name__ == "__main__":
    main()
