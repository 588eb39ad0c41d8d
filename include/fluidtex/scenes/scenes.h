/// @file scenes.h
/// @brief Deterministic example scenes with analytic velocities, mirroring the
/// test cases of Gagnon et al. 2019 (Sec. 7, Figs. 8–10, 13):
///  - `rotation` (Fig. 8): the unit disc at the origin, meshed with concentric
///    rings (ring spacing 2 / resolution, 6 k vertices on ring k: 6 n^2
///    faces), static; rigid rotation v = w x r with w = (pi/2) / 4 s.
///  - `split` (Fig. 9, "split Y"): potential flow past the tip of a wedge
///    divider, psi = -U r^n sin(n phi) (phi from the -y axis, n = 6/5, branch
///    axes at +-30 deg from the vertical); domain {|psi| <= 0.32 U, outside
///    the wedge, r <= 1} in [-0.75,0.75] x [-1,0.9]: inflow at the bottom of
///    the stem, outflow at the two branch ends, walls are streamlines,
///    speed ~0.9 units/s. Static domain.
///  - `merge` (Fig. 10): a 2D metaball region (two Gaussian blobs) whose
///    centres move apart and back (one → two → one component over the
///    sequence) while the pair turns by 60 deg; triangulated each frame by
///    marching triangles on a grid over [-1.4,1.4]^2, so the outline,
///    vertex count and topology change between frames.
///  - `drop` (Fig. 13): 3D, a sphere (radius 0.25) falling into a pool (the
///    rounded box [-1,1]^2 x [-0.5,0]) and merging with it through a smooth
///    union; contact at mid-sequence. Each frame is sampled into an OpenVDB
///    level set (voxel 2.2 / resolution) and meshed with volumeToMesh:
///    closed, outward-oriented surface.
///  - `pour`: 3D, a jet from a nozzle 0.8 above the same pool, falling
///    under gravity (it thins as it speeds up) and landing about 9 frames
///    in (24 fps); the pool's top is drawn towards it and its level rises
///    with the poured volume. Surface is made where the jet leaves the
///    nozzle (the liquid enters through the nozzle's cap) and destroyed
///    where it plunges, every frame: sources and sinks inside a closed
///    mesh (scene_pour.cpp). Meshed as `drop` is.
///  - `stream`, `stream-rock`: open boundaries. A fixed window of a channel,
///    [-1.5, 1.5] x [-0.5, 0.5], through which the liquid moves in +x at
///    about 1.2 units/s (stream: uniformly, the liquid moving rigidly;
///    stream-rock: potential flow past a cylinder of radius 0.2 at the
///    origin between streamline walls): surface is made at the inflow edge
///    x = -1.5 and destroyed at the outflow edge x = 1.5 every frame, and
///    kept everywhere else (divergence-free flows). Grid spacing
///    3 / resolution.
/// Flat scenes lie in z = 0 with counter-clockwise triangles (normals +z).
/// Every frame is an independent FrameMesh whose velocities (scene units per
/// second, analytic at the vertices) carry the surface of frame f to that of
/// frame f+1 over dt = 1/fps; frame f is at time (f - 1) / fps.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fluidtex/geometry/mesh.h"
#include "fluidtex/scenes/scene_options.h"

namespace fluidtex {

/// Names accepted by make_scene_frame.
std::vector<std::string> scene_names();

/// One frame (1-based) of a scene. Throws InputError for an unknown name or
/// an invalid option.
FrameMesh make_scene_frame(const std::string& scene, int frame, const SceneOptions& options);

/// Writes frames 1..options.frames as binary PLY (`x y z vx vy vz`, float)
/// to `dir/<scene>.####.ply`, or as VDB (the scene's voxel size, velocity
/// over the level set's narrow band) to `dir/<scene>.####.vdb`; returns the
/// pattern written.
std::string write_scene(const std::string& scene, const std::string& dir, const SceneOptions& options);

/// Writes one frame as binary little-endian PLY with float `x y z vx vy vz`,
/// atomically (used by `gen` and by tests); with `fps`, a header comment
/// states the frame rate (`comment fps=24`), which `run` reads.
void write_frame_ply(const std::string& path, const FrameMesh& mesh, std::optional<double> fps = std::nullopt);

}  // namespace fluidtex
