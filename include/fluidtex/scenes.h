/// @file scenes.h
/// @brief Deterministic example scenes with analytic velocities, mirroring the
/// test cases of Gagnon et al. 2019 (Sec. 7, Figs. 8–10, 13):
///  - `rotation`: a flat disc rotating rigidly about its centre (Fig. 8);
///  - `split`: a flat channel flow that splits into two branches (Fig. 9);
///  - `merge`: a flat fluid region that splits in two and merges again, so
///    the outline and topology change between frames (Fig. 10);
///  - `drop`: 3D, a liquid sphere falling into a pool and merging with it;
///    each frame is an iso-surface of an implicit function extracted with
///    OpenVDB's volumeToMesh, velocities analytic at the vertices.
/// Every frame is a FrameMesh whose velocities (scene units per second) carry
/// the surface of frame f to that of frame f+1 over dt = 1/fps.
#pragma once

#include <string>
#include <vector>

#include "fluidtex/mesh.h"

namespace fluidtex {

struct SceneOptions {
  int frames = 48;        ///< number of frames written (1..frames)
  double fps = 24.0;      ///< frame rate the velocities refer to
  /// Mesh density: cells across the scene's extent (2D: grid cells across the
  /// domain; 3D: voxels across the domain). Face counts grow as resolution²
  /// for all scenes.
  int resolution = 64;
};

/// Names accepted by make_scene_frame.
std::vector<std::string> scene_names();

/// One frame (1-based) of a scene. Throws InputError for an unknown name or
/// an invalid option.
FrameMesh make_scene_frame(const std::string& scene, int frame, const SceneOptions& options);

/// Writes frames 1..options.frames as binary PLY (`x y z vx vy vz`, float)
/// to `dir/<scene>.####.ply`; returns the pattern written.
std::string write_scene(const std::string& scene, const std::string& dir,
                        const SceneOptions& options);

/// Writes one frame as binary little-endian PLY with float `x y z vx vy vz`,
/// atomically (used by `gen` and by tests).
void write_frame_ply(const std::string& path, const FrameMesh& mesh);

}  // namespace fluidtex
