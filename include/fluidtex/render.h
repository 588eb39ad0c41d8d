/// @file render.h
/// @brief A small software renderer for looking at results without a DCC:
/// the textured UV mesh of a frame drawn with its atlas (bilinear lookup),
/// an orthographic camera along an axis, a z-buffer and simple Lambert
/// shading. Deterministic; used by `fluidtex preview` and for the images in
/// docs/.
#pragma once

#include <string>

#include "fluidtex/image_io.h"
#include "fluidtex/uv_mesh_writer.h"

namespace fluidtex {

enum class View { Top, Front, Side };  ///< look along −z, +y, −x

View view_from_string(const std::string& s);

struct RenderOptions {
  int width = 768;               ///< image width; height follows the framing
  View view = View::Top;
  bool shade = true;             ///< Lambert shading with a light over the camera
  /// Region to frame (scene units, the two screen axes); empty = the mesh's bounds.
  double min_u = 0, min_v = 0, max_u = 0, max_v = 0;
};

/// Renders `mesh` textured with `atlas` (linear RGB or grey); returns a
/// linear RGB image (background dark grey).
Image render_textured(const UVMesh& mesh, const Image& atlas, const RenderOptions& options);

/// Reads a UV mesh written by write_uv_mesh_obj (v, vt, vn, f v/vt/vn) through
/// OpenMesh; InputError when the file is missing or malformed.
UVMesh read_uv_mesh_obj(const std::string& path);

}  // namespace fluidtex
