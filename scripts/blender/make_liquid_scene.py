"""Build and bake a small Mantaflow liquid test scene (Blender 3.4, headless).

Command line:

    blender -b --factory-startup --python-exit-code 1 \
        --python scripts/blender/make_liquid_scene.py -- \
        --output scene/drop.blend --cache scene/cache \
        [--resolution 32] [--frames 24] [--size 1.0] [--data-format OPENVDB|UNI]

What it builds, starting from the factory-startup scene (all of it is deleted):

* "Domain": a closed box of edge `--size` metres (default 1 m) standing on
  z = 0, made from a 2-unit cube scaled by size/2, so its matrix_world is not
  the identity (exporters must apply it). Liquid domain, resolution
  `--resolution` (default 32) along the longest side, collision on all six
  borders, mesh enabled (use_mesh) with mesh velocities (use_speed_vectors,
  the "velocity" point attribute of the evaluated mesh), cache type ALL,
  data cache format `--data-format` (default OPENVDB), mesh cache format
  Binary Object, cache directory `--cache` (made absolute; Blender stores it
  relative to the .blend, "//...", when it saves).
  Blender 3.4.1 quirk: with OpenVDB data, the mesh velocities are never
  written (Mantaflow saves them with the data format as lVelMesh_####.vdb,
  which fails silently), so the "velocity" attribute is all zeros;
  export_fluid.py then samples the velocity grid instead. With
  --data-format UNI the attribute is filled (mesh/lVelMesh_####.uni).
* "Liquid": a sphere of radius 0.15 x size centred at z = 0.78 x size, a
  liquid flow object with Geometry behaviour (no inflow): the liquid exists
  from the first frame and falls under scene gravity (0, 0, -9.81 m/s^2),
  reaching the floor after about 8 frames at 24 fps, then splashes.
* Frames 1..`--frames` (default 24) at 24 fps, scene units metres, scale 1.

The bake runs bpy.ops.fluid.bake_all in exec mode (synchronous in background
mode: it returns when the bake is done) inside
context.temp_override(object=domain, active_object=domain, ...); its poll
needs an active object ("Context missing active object" otherwise). Then the
.blend is saved to `--output`. At resolution 32 and 24 frames the bake
takes 2.5-3.5 s on 2 cores (resolution 48 and 30 frames: about 20 s).
The script bakes a new domain only: re-baking an already baked domain from
a script in the same Blender process is unreliable in 3.4.1 (bake_all returns
FINISHED at once without writing, and free_all followed by bake_all
crashed).

Errors are reported as one line on stderr; the exit status is then 1.
"""

import argparse
import os
import sys
import time

import bpy


def fail(msg):
    sys.stderr.write("make_liquid_scene: error: %s\n" % msg)
    sys.exit(1)


class OneLineParser(argparse.ArgumentParser):
    """argparse, but a usage error is one line on stderr and exit status 1."""

    def error(self, message):
        fail(message)


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = OneLineParser(
        prog="make_liquid_scene.py",
        description="Build and bake a small Mantaflow liquid test scene.")
    p.add_argument("--output", required=True, help="path of the .blend to save")
    p.add_argument("--cache", required=True, help="fluid cache directory")
    p.add_argument("--resolution", type=int, default=32,
                   help="domain resolution along its longest side (default 32)")
    p.add_argument("--frames", type=int, default=24,
                   help="number of frames, starting at 1 (default 24)")
    p.add_argument("--size", type=float, default=1.0,
                   help="domain edge length in metres (default 1.0)")
    p.add_argument("--data-format", choices=("OPENVDB", "UNI"), default="OPENVDB",
                   help="data cache format (default OPENVDB; UNI also keeps the "
                        "mesh velocities, see above)")
    a = p.parse_args(argv)
    if a.resolution < 6 or a.resolution > 512:
        p.error("--resolution must be in 6..512")
    if a.frames < 1:
        p.error("--frames must be at least 1")
    if not a.size > 0:
        p.error("--size must be positive")
    return a


def clear_scene():
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.materials, bpy.data.cameras,
                 bpy.data.lights):
        for block in list(coll):
            coll.remove(block)


def add_mesh_object(name, mesh):
    ob = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(ob)
    return ob


def make_cube_mesh(name):
    """A 2-unit cube centred at the origin (like Blender's default cube)."""
    verts = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1),
             (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    me = bpy.data.meshes.new(name)
    me.from_pydata(verts, [], faces)
    me.update()
    return me


def make_sphere_mesh(name, radius, segments=32, rings=16):
    import math
    verts = [(0.0, 0.0, radius)]
    for r in range(1, rings):
        th = math.pi * r / rings
        for s in range(segments):
            ph = 2.0 * math.pi * s / segments
            verts.append((radius * math.sin(th) * math.cos(ph),
                          radius * math.sin(th) * math.sin(ph),
                          radius * math.cos(th)))
    verts.append((0.0, 0.0, -radius))
    bottom = len(verts) - 1
    faces = []
    for s in range(segments):
        faces.append((0, 1 + s, 1 + (s + 1) % segments))
    for r in range(rings - 2):
        a0 = 1 + r * segments
        b0 = a0 + segments
        for s in range(segments):
            s1 = (s + 1) % segments
            faces.append((a0 + s, b0 + s, b0 + s1, a0 + s1))
    last = 1 + (rings - 2) * segments
    for s in range(segments):
        faces.append((last + s, bottom, last + (s + 1) % segments))
    me = bpy.data.meshes.new(name)
    me.from_pydata(verts, [], faces)
    me.update()
    return me


def main():
    a = parse_args()
    output = os.path.abspath(a.output)
    cache = os.path.abspath(a.cache)
    try:
        os.makedirs(cache, exist_ok=True)
        os.makedirs(os.path.dirname(output), exist_ok=True)
    except OSError as e:
        fail("cannot create folder: %s" % e)

    clear_scene()
    scene = bpy.context.scene
    scene.frame_start = 1
    scene.frame_end = a.frames
    scene.frame_current = 1
    scene.render.fps = 24
    scene.render.fps_base = 1.0
    scene.unit_settings.system = 'METRIC'
    scene.unit_settings.scale_length = 1.0
    scene.use_gravity = True
    scene.gravity = (0.0, 0.0, -9.81)

    size = a.size
    # Domain: 2-unit cube scaled by size/2, bottom face on z = 0.
    dom = add_mesh_object("Domain", make_cube_mesh("DomainMesh"))
    dom.scale = (size / 2.0,) * 3
    dom.location = (0.0, 0.0, size / 2.0)

    # Liquid sphere near the top of the domain.
    liq = add_mesh_object("Liquid", make_sphere_mesh("LiquidMesh", 0.15 * size))
    liq.location = (0.0, 0.0, 0.78 * size)
    liq.hide_render = True

    view_layer = bpy.context.view_layer
    view_layer.update()

    mod = dom.modifiers.new("Fluid", 'FLUID')
    mod.fluid_type = 'DOMAIN'
    ds = mod.domain_settings
    ds.domain_type = 'LIQUID'
    ds.resolution_max = a.resolution
    for side in ("front", "back", "right", "left", "top", "bottom"):
        setattr(ds, "use_collision_border_" + side, True)
    ds.use_mesh = True
    if hasattr(ds, "use_speed_vectors"):
        ds.use_speed_vectors = True
    ds.cache_type = 'ALL'
    ds.cache_directory = cache
    ds.cache_frame_start = 1
    ds.cache_frame_end = a.frames
    try:
        ds.cache_data_format = a.data_format
    except TypeError as e:
        fail("data cache format %s unavailable: %s" % (a.data_format, e))
    ds.cache_mesh_format = 'BOBJECT'
    ds.time_scale = 1.0

    fmod = liq.modifiers.new("Fluid", 'FLUID')
    fmod.fluid_type = 'FLOW'
    fs = fmod.flow_settings
    fs.flow_type = 'LIQUID'
    fs.flow_behavior = 'GEOMETRY'
    fs.flow_source = 'MESH'
    fs.use_initial_velocity = False

    # Select the domain and make it active for the bake operator.
    for ob in scene.objects:
        ob.select_set(False)
    dom.select_set(True)
    view_layer.objects.active = dom
    view_layer.update()

    t0 = time.time()
    with bpy.context.temp_override(scene=scene, view_layer=view_layer,
                                   object=dom, active_object=dom,
                                   selected_objects=[dom]):
        result = bpy.ops.fluid.bake_all()
    if 'FINISHED' not in result:
        fail("fluid.bake_all returned %s" % sorted(result))
    if not ds.has_cache_baked_data:
        fail("bake finished but the domain has no baked data in %s" % cache)
    mesh_dir = os.path.join(cache, "mesh")
    if not ds.has_cache_baked_mesh or not os.path.isdir(mesh_dir):
        fail("bake finished but no liquid mesh was baked in %s" % mesh_dir)
    sys.stderr.write("make_liquid_scene: baked %d frames at resolution %d in %.1f s\n"
                     % (a.frames, a.resolution, time.time() - t0))

    scene.frame_set(1)
    try:
        bpy.ops.wm.save_as_mainfile(filepath=output, check_existing=False)
    except RuntimeError as e:
        fail("cannot save %s: %s" % (output, str(e).strip().splitlines()[-1]))
    sys.stderr.write("make_liquid_scene: saved %s\n" % output)


if __name__ == "__main__":
    main()
