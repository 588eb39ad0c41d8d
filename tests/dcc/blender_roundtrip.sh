#!/usr/bin/env bash
# Blender round trip of fluidtex: bake a small Mantaflow liquid, export it as a
# PLY sequence with velocities, texture it with fluidtex (PLY and OBJ UV
# meshes), load the results back into Blender and check them.
#
# Usage: blender_roundtrip.sh FLUIDTEX_EXE SOURCE_DIR WORK_DIR
#
# Needs Blender 3.4 as `blender` on PATH (or $BLENDER); without it the test
# prints "blender not found: skipped" and exits 77 (CTest: SKIP_RETURN_CODE 77).
# WORK_DIR is removed and made anew at the start and removed again on
# success; on failure it is kept, with the logs of every step in WORK_DIR/logs.
#
# Steps (the wall time of each is printed):
#  1. make_liquid_scene.py: a liquid sphere falling in a 1 m box, resolution
#     32, 10 frames (the bake takes 1.5-2 s; it hits the floor after frame 8).
#     Resolution 32 rather than 24: at 24 the surface is too coarse for the
#     free-fall tolerances below (first vz increment 2.01 % off -g/fps, and
#     fps x mean-z step 2->3 8.4 % off vz); at 32 they hold with margin
#     (0.22 % and 2.8 % at worst).
#  2. export_fluid.py to WORK_DIR/ply, then check_free_fall.py on frames 1-5
#     (all before the impact): mean vz increments within 2 % of -g/fps, and
#     fps x mean-z step within 5 % of vz.
#  3. fluidtex run, frames 1-6, 512x512 atlases: once with PLY UV meshes
#     (WORK_DIR/out/mesh.####.ply), once with the default OBJ meshes
#     (WORK_DIR/out-obj); and once in UDIM tiles (WORK_DIR/out-udim,
#     --texel-density 300 in tiles of 128x128, atlas.####.<UDIM>.exr).
#  4. load_fluidtex.py --check --save on all three outputs: 6 frames, UVs, the
#     first frame's atlas exists; PLY: format ply, velocities loaded and
#     non-zero; UDIM: more than one tile, and UVs beyond tile 1001.
#  5. The saved .blend of the PLY run, reloaded: on frame 3 exactly one loaded
#     object renders, and its mesh has the vertex count of mesh.0003.ply.
#  6. The saved .blend of the UDIM run, rendered (Cycles, 160x120, frame 3):
#     the liquid covers pixels and none of them is the magenta of a missing
#     texture tile.
set -euo pipefail

if [ $# -ne 3 ]; then
  echo "usage: $0 FLUIDTEX_EXE SOURCE_DIR WORK_DIR" >&2
  exit 2
fi
FLUIDTEX=$1
SRC=$2
WORK=$3

BLENDER=${BLENDER:-}
if [ -z "$BLENDER" ]; then
  BLENDER=$(command -v blender || true)
fi
if [ -z "$BLENDER" ] || [ ! -x "$BLENDER" ]; then
  echo "blender not found: skipped"
  exit 77
fi

case $FLUIDTEX in /*) ;; *) FLUIDTEX=$PWD/$FLUIDTEX ;; esac
case $SRC in /*) ;; *) SRC=$PWD/$SRC ;; esac
case $WORK in /*) ;; *) WORK=$PWD/$WORK ;; esac
SCRIPTS=$SRC/scripts/blender
HERE=$SRC/tests/dcc
if [ ! -x "$FLUIDTEX" ]; then
  echo "FAIL: $FLUIDTEX is not an executable" >&2
  exit 1
fi

case $WORK in / | "$HOME" | "$SRC" | "$SRC"/ | "$PWD") echo "FAIL: refusing WORK_DIR $WORK" >&2; exit 1 ;; esac
rm -rf "$WORK"
mkdir -p "$WORK/logs"
LOGS=$WORK/logs

now() {
  if [ -n "${EPOCHREALTIME:-}" ]; then echo "$EPOCHREALTIME"; else date +%s.%N; fi
}
T_ALL=$(now)
STEP=""
T_STEP=""

begin() {
  STEP=$1
  T_STEP=$(now)
  echo "== $STEP"
}

end() {
  awk -v a="$T_STEP" -v b="$(now)" -v s="$STEP" 'BEGIN { printf "   %s: %.1f s\n", s, b - a }'
}

fail() {
  echo "FAIL ($STEP): $*" >&2
  echo "(work folder kept: $WORK)" >&2
  exit 1
}

# run LOG CMD...: runs CMD with stdout and stderr in $LOGS/LOG; on failure
# shows the end of the log and fails.
run() {
  local log=$LOGS/$1
  shift
  if ! "$@" >"$log" 2>&1; then
    tail -n 20 "$log" >&2
    fail "$(basename "$1") exited with an error (log: $log)"
  fi
}

blender_py() {  # blender_py LOG [BLEND] SCRIPT -- ARGS...
  local log=$1 blend=()
  shift
  if [ "${1##*.}" = blend ]; then
    blend=("$1")
    shift
  fi
  local script=$1
  shift
  run "$log" "$BLENDER" -b --factory-startup "${blend[@]}" --python-exit-code 1 --python "$script" "$@"
}

# json_check FILE MODE: checks the load_fluidtex.py --check JSON line in FILE
# (python3 when there is one, else Blender's Python).
JSON_CHECK='
import json, sys
path, mode = sys.argv[-2], sys.argv[-1]
lines = [l for l in open(path) if l.startswith("{\"frames\"")]
if len(lines) != 1:
    sys.stderr.write("no --check JSON line in %s\n" % path)
    sys.exit(1)
d = json.loads(lines[0])
bad = []
if d["frames"] != 6 or d["first_frame"] != 1 or d["last_frame"] != 6:
    bad.append("frames %s (%s-%s), expected 6 (1-6)" % (d["frames"], d["first_frame"], d["last_frame"]))
if not d["uvs"]:
    bad.append("no UVs")
if not d["image_first_exists"]:
    bad.append("first atlas %s does not exist" % d["image_first"])
if d["format"] != {"udim": "obj"}.get(mode, mode):
    bad.append("format %s, expected %s" % (d["format"], mode))
if mode == "ply" and not (d["velocities"] and d["velocity_max_first"] > 0):
    bad.append("velocities %s, max |v| of frame 1 %s: expected non-zero" % (d["velocities"], d["velocity_max_first"]))
if mode == "obj" and d["velocities"]:
    bad.append("velocities from OBJ meshes")
if mode == "udim" and not (d["image_tiles_first"] > 1 and d["uv_udim_max_first"] > 1001):
    bad.append("%s UDIM tiles, UVs up to tile %s: expected more than one" % (d["image_tiles_first"],
                                                                              d["uv_udim_max_first"]))
if bad:
    sys.stderr.write("; ".join(bad) + "\n")
    sys.exit(1)
print("%s: %d frames, %d vertices on frame 1, UVs, atlas %s (%d tiles), velocities %s (max |v| %.4f)" % (
    mode, d["frames"], d["vertices_first"], d["image_first"], d["image_tiles_first"], d["velocities"],
    d["velocity_max_first"]))
'
json_check() {
  local out
  if command -v python3 >/dev/null 2>&1; then
    out=$(python3 -c "$JSON_CHECK" "$1" "$2" 2>&1) || fail "$out"
  else
    out=$("$BLENDER" -b --factory-startup --python-exit-code 1 --python-expr "$JSON_CHECK" -- "$1" "$2" 2>&1) ||
      fail "$(echo "$out" | grep -v '^Blender\|^$' | tail -n 1)"
    out=$(echo "$out" | grep "^$2: ")
  fi
  echo "   $out"
}

# 1. Bake.
begin "1 bake (make_liquid_scene.py)"
blender_py bake.log "$SCRIPTS/make_liquid_scene.py" -- \
  --output "$WORK/drop.blend" --cache "$WORK/cache" --resolution 32 --frames 10
grep "baked" "$LOGS/bake.log" | sed 's/^/   /' || true
end

# 2. Export and free-fall check.
begin "2 export (export_fluid.py) + free-fall check"
blender_py export.log "$WORK/drop.blend" "$SCRIPTS/export_fluid.py" -- --output "$WORK/ply"
shopt -s nullglob
firsts=("$WORK"/ply/*.0001.ply)
shopt -u nullglob
[ ${#firsts[@]} -eq 1 ] || fail "expected one *.0001.ply in $WORK/ply, found ${#firsts[@]}"
NAME=$(basename "${firsts[0]}" .0001.ply)
for f in 0001 0002 0003 0004 0005 0006; do
  [ -f "$WORK/ply/$NAME.$f.ply" ] || fail "$WORK/ply/$NAME.$f.ply was not exported"
done
if ! "$BLENDER" -b --factory-startup --python-exit-code 1 --python "$HERE/check_free_fall.py" -- \
  "$WORK/ply" --frames 1-5 --fps 24 --g 9.81 >"$LOGS/free_fall.log" 2>&1; then
  fail "$(grep 'check_free_fall: FAIL' "$LOGS/free_fall.log" || tail -n 1 "$LOGS/free_fall.log")"
fi
grep -E '^(frame|vz increment|fps x|check_free_fall)' "$LOGS/free_fall.log" | sed 's/^/   /'
end

# 3. fluidtex, PLY and OBJ UV meshes.
begin "3 fluidtex run (PLY meshes, then OBJ meshes)"
run fluidtex_ply.log "$FLUIDTEX" run -q -i "$WORK/ply/$NAME.####.ply" -e "$SRC/data/gravel.png" \
  -o "$WORK/out" --frames 1-6 --atlas-size 512 --mesh "$WORK/out/mesh.####.ply"
run fluidtex_obj.log "$FLUIDTEX" run -q -i "$WORK/ply/$NAME.####.ply" -e "$SRC/data/gravel.png" \
  -o "$WORK/out-obj" --frames 1-6 --atlas-size 512
run fluidtex_udim.log "$FLUIDTEX" run -q -i "$WORK/ply/$NAME.####.ply" -e "$SRC/data/gravel.png" \
  -o "$WORK/out-udim" --frames 1-6 --texel-density 300 --atlas-size 128 --atlas "$WORK/out-udim/atlas.####.<UDIM>.exr"
for f in 0001 0006; do
  for p in out/mesh.$f.ply out/atlas.$f.exr out-obj/mesh.$f.obj out-obj/atlas.$f.exr out-udim/mesh.$f.obj \
    out-udim/atlas.$f.1001.exr out-udim/atlas.$f.1002.exr; do
    [ -f "$WORK/$p" ] || fail "fluidtex did not write $WORK/$p"
  done
done
end

# 4. Load both outputs.
begin "4 load (load_fluidtex.py --check --save)"
blender_py load_ply.log "$SCRIPTS/load_fluidtex.py" -- --input "$WORK/out" --clear-scene \
  --check --save "$WORK/out.blend"
json_check "$LOGS/load_ply.log" ply
blender_py load_obj.log "$SCRIPTS/load_fluidtex.py" -- --input "$WORK/out-obj" --clear-scene \
  --check --save "$WORK/out-obj.blend"
json_check "$LOGS/load_obj.log" obj
blender_py load_udim.log "$SCRIPTS/load_fluidtex.py" -- --input "$WORK/out-udim" --clear-scene \
  --check --save "$WORK/out-udim.blend"
json_check "$LOGS/load_udim.log" udim
end

# 5. Reload the PLY run's .blend: visibility on frame 3 and vertex count.
begin "5 reload saved .blend (frame 3)"
cat >"$WORK/check_reload.py" <<'EOF'
import sys
import bpy

ply = sys.argv[sys.argv.index("--") + 1]
with open(ply, "rb") as fh:
    head = fh.read(4096).split(b"end_header")[0].decode("ascii", "replace")
count = [int(l.split()[2]) for l in head.splitlines() if l.startswith("element vertex")]
scene = bpy.context.scene
scene.frame_set(3)
coll = bpy.data.collections.get("fluidtex")
if coll is None:
    sys.stderr.write("check_reload: FAIL: no collection 'fluidtex'\n")
    sys.exit(1)
shown = [o for o in coll.objects if o.type == 'MESH' and not o.hide_render]
if len(shown) != 1:
    sys.stderr.write("check_reload: FAIL: %d objects render on frame 3 (%s)\n"
                     % (len(shown), ", ".join(o.name for o in shown)))
    sys.exit(1)
ob = shown[0]
nv = len(ob.data.vertices)
if len(count) != 1 or nv != count[0]:
    sys.stderr.write("check_reload: FAIL: %s has %d vertices, %s says %s\n" % (ob.name, nv, ply, count))
    sys.exit(1)
has_vel = "velocity" in ob.data.attributes
print("check_reload: OK: frame 3 renders %s only, %d vertices (as %s), velocity attribute %s"
      % (ob.name, nv, ply.rsplit("/", 1)[-1], has_vel))
EOF
if ! "$BLENDER" -b --factory-startup "$WORK/out.blend" --python-exit-code 1 --python "$WORK/check_reload.py" -- \
  "$WORK/out/mesh.0003.ply" >"$LOGS/reload.log" 2>&1; then
  fail "$(grep 'check_reload: FAIL' "$LOGS/reload.log" || tail -n 1 "$LOGS/reload.log")"
fi
grep '^check_reload: OK' "$LOGS/reload.log" | sed 's/^/   /'
end

# 6. Render the UDIM run: every tile found, none missing (magenta).
begin "6 render the UDIM run (frame 3)"
cat >"$WORK/check_udim_render.py" <<'EOF'
import sys
import bpy
import mathutils

out = sys.argv[sys.argv.index("--") + 1]
scene = bpy.context.scene
scene.frame_set(3)
shown = [o for o in bpy.data.collections["fluidtex"].objects if o.type == 'MESH' and not o.hide_render]
box = [o.matrix_world @ mathutils.Vector(c) for o in shown for c in o.bound_box]
centre = sum(box, mathutils.Vector()) / len(box)
size = max((p - centre).length for p in box)
cam = bpy.data.objects.new("check_camera", bpy.data.cameras.new("check_camera"))
scene.collection.objects.link(cam)
cam.location = centre + mathutils.Vector((1.0, -1.0, 1.4)) * 2.5 * size
cam.rotation_euler = (centre - cam.location).to_track_quat('-Z', 'Y').to_euler()
scene.camera = cam
sun = bpy.data.objects.new("check_sun", bpy.data.lights.new("check_sun", 'SUN'))
scene.collection.objects.link(sun)
scene.world = scene.world or bpy.data.worlds.new("check_world")
scene.world.use_nodes = False
scene.world.color = (0.0, 0.0, 0.0)
scene.render.engine = 'CYCLES'
scene.cycles.samples = 4
scene.cycles.use_denoising = False
scene.render.resolution_x, scene.render.resolution_y = 160, 120
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
img = bpy.data.images.load(out)
px = list(img.pixels)
lit = magenta = 0
for i in range(0, len(px), 4):
    r, g, b = px[i], px[i + 1], px[i + 2]
    lit += r + g + b > 0.05
    magenta += r > 0.8 and b > 0.8 and g < 0.2
tiles = [len(i.tiles) for i in bpy.data.images if i.source == 'TILED']
if lit < 500 or magenta > 0 or not tiles:
    sys.stderr.write("check_udim_render: FAIL: %d liquid pixels, %d magenta, tiled images %s\n" % (lit, magenta, tiles))
    sys.exit(1)
print("check_udim_render: OK: %d liquid pixels, none magenta; tiles per image %d-%d" % (lit, min(tiles), max(tiles)))
EOF
if ! "$BLENDER" -b "$WORK/out-udim.blend" --python-exit-code 1 --python "$WORK/check_udim_render.py" -- \
  "$WORK/udim.png" >"$LOGS/udim_render.log" 2>&1; then
  fail "$(grep 'check_udim_render: FAIL' "$LOGS/udim_render.log" || tail -n 1 "$LOGS/udim_render.log")"
fi
grep '^check_udim_render: OK' "$LOGS/udim_render.log" | sed 's/^/   /'
end

[ -n "${KEEP_WORK:-}" ] || rm -rf "$WORK"
awk -v a="$T_ALL" -v b="$(now)" 'BEGIN { printf "PASS (%.1f s)\n", b - a }'
