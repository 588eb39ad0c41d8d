/// @file textured_frame.h
/// @brief One frame of a finished run as `eval` and `compare` read it: its
/// UV mesh and atlas, and the atlas colour at any point of the surface.
#pragma once

#include <memory>
#include <string>
#include <utility>

#include "fluidtex/geometry/image.h"
#include "fluidtex/geometry/mesh.h"
#include "fluidtex/geometry/surface.h"
#include "fluidtex/geometry/uv_mesh.h"

namespace fluidtex {

/// A textured surface at one frame: the UV mesh, its atlas (one image or
/// UDIM tiles) and a closest point index over the mesh.
struct TexturedFrame {
  UVMesh mesh;
  TiledAtlas atlas;
  std::unique_ptr<const FrameMesh> geometry;  ///< mesh positions/triangles (what `surface` indexes)
  std::unique_ptr<SurfaceIndex> surface;

  TexturedFrame(UVMesh m, TiledAtlas a);
  TexturedFrame(UVMesh m, Image a) : TexturedFrame(std::move(m), TiledAtlas::one(std::move(a))) {}
  /// Colour of the surface point nearest to `p` (atlas lookup at its uv).
  void color_at(const Vec3& p, float* out) const;
};

/// The most channels an atlas may have for TexturedFrame::color_at's callers
/// (RGBA; fluidtex writes 1, 3 or 4).
constexpr int kMaxLookupChannels = 4;

/// Frame `frame`'s atlas from its pattern: one image, or with <UDIM> every
/// tile on disk; InputError naming the file when it (tile 1001) is missing,
/// a tile has more than kMaxLookupChannels channels, or tiles differ in
/// channels.
TiledAtlas read_frame_atlas(const std::string& atlas_pattern, int frame);

/// Frame `frame` of a finished run: its atlas (read_frame_atlas) and its UV
/// mesh (OBJ) from the run's patterns; InputError naming the file when one
/// is missing or unfit.
TexturedFrame read_run_frame(const std::string& atlas_pattern, const std::string& mesh_pattern, int frame);

}  // namespace fluidtex
