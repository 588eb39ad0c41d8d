/// @file render.h
/// @brief A small software renderer for looking at results without a DCC:
/// the textured UV mesh of a frame drawn with its atlas (bilinear lookup),
/// an orthographic camera along an axis or a perspective camera, a z-buffer
/// and simple Lambert shading. Besides the colour image it returns a G-buffer
/// (per pixel: visible triangle, barycentric coordinates, depth) and the
/// camera, so that other tools can relate pixels to the surface (e.g. the
/// projected fluid velocity at a pixel, compared with optical flow).
/// Deterministic; used by `fluidtex preview` and for the images in docs/.
///
/// Pixel convention everywhere: x right, y down, pixel (i, j) covers
/// [i, i+1) × [j, j+1), so its centre is (i + 0.5, j + 0.5); row 0 at the top.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "fluidtex/geometry/image.h"
#include "fluidtex/geometry/mesh.h"
#include "fluidtex/geometry/uv_mesh.h"
#include "fluidtex/util/enum_names.h"

namespace fluidtex {

enum class View { Top, Front, Side };  ///< look along −z, +y, −x

inline constexpr EnumName<View> kViewNames[] = {{View::Top, "top"}, {View::Front, "front"}, {View::Side, "side"}};
constexpr const auto& enum_names(View) { return kViewNames; }

/// Maps scene points to pixels. Orthographic along an axis (View; framed by a
/// region of the two screen axes) or perspective (eye, target, vertical field
/// of view). Perspective up is +z (the scenes' up axis) unless the view
/// direction is within ~8° of it, then +y.
struct Camera {
  bool perspective = false;
  int width = 0, height = 0;  ///< image size in pixels

  // Orthographic: screen u right, v up (see View); pixel x = (u − min_u)·scale,
  // y = (max_v − v)·scale.
  View view = View::Top;
  double min_u = 0, max_v = 0, scale = 1;

  // Perspective: an orthonormal frame (right, up, forward) at the eye.
  Vec3 eye = Vec3::Zero(), target = Vec3(0, 0, -1);
  double fov_deg = 40.0;  ///< vertical field of view
  double focal = 1.0;     ///< focal length in pixels
  Vec3 right = Vec3::UnitX(), up = Vec3::UnitY(), forward = -Vec3::UnitZ();
  double near = 1e-6;  ///< points with depth ≤ near are behind the camera

  /// An orthographic camera over the region [min_u, max_u] × [min_v, max_v]
  /// of the view's screen axes; height follows the region's aspect.
  static Camera orthographic(View view, double min_u, double min_v, double max_u, double max_v, int width);
  /// A perspective camera at `eye` looking at `target`; InputError when they
  /// coincide or the field of view is not in (0, 180).
  static Camera perspective_at(const Vec3& eye, const Vec3& target, double fov_deg, int width, int height);

  /// (pixel x, pixel y, depth). Depth grows away from the camera: the
  /// distance along the view direction (perspective; ≤ near: behind the
  /// camera, x and y meaningless) or −(p · axis towards the camera)
  /// (orthographic, any sign).
  Vec3 project(const Vec3& p) const;
  /// Unit vector from `p` towards the camera (constant when orthographic).
  Vec3 toward_camera(const Vec3& p) const;
  /// True when project(p) is in front of the camera.
  bool in_front(const Vec3& p) const { return !perspective || project(p).z() > near; }
  /// Image-space displacement (pixels, x right, y down) of a 3D displacement
  /// `d` at the point `p`: project(p + d) − project(p). For a velocity v over
  /// a frame step dt, d = v·dt gives the flow in pixels per frame.
  Vec2 image_displacement(const Vec3& p, const Vec3& d) const;
};

struct RenderOptions {
  int width = 768;  ///< image width
  View view = View::Top;
  bool shade = true;  ///< Lambert shading with a light over the camera
  /// Orthographic region to frame (scene units, the two screen axes); empty =
  /// the mesh's bounds plus 3%. The image height follows the framing.
  double min_u = 0, min_v = 0, max_u = 0, max_v = 0;
  /// Perspective camera (replaces the orthographic view when set).
  bool perspective = false;
  Vec3 eye = Vec3::Zero(), target = Vec3::Zero();
  double fov_deg = 40.0;  ///< vertical field of view, degrees
  int height = 0;         ///< perspective image height; 0 = width·3/4
};

/// `options` with the orthographic framing fixed to the bounds (plus 3%) of
/// `positions` (unchanged when a framing is given or the camera is a
/// perspective one): renders of several frames then share one camera.
RenderOptions framed(const std::vector<Vec3>& positions, const RenderOptions& options);

/// The camera render() uses for `positions` (framing resolved).
Camera make_camera(const std::vector<Vec3>& positions, const RenderOptions& options);

/// Per pixel (index y·width + x): the visible triangle, the barycentric
/// coordinates of the visible surface point in that triangle (weights of its
/// corners 0, 1, 2, perspective-correct: the 3D point is Σ b_k p_k) and its
/// depth (Camera::project's z). Background: face −1, bary 0, depth +inf.
struct GBuffer {
  int width = 0, height = 0;
  std::vector<int> face;
  std::vector<Vec3> bary;
  std::vector<double> depth;

  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * width + x; }
  int face_at(int x, int y) const { return face[index(x, y)]; }
  const Vec3& bary_at(int x, int y) const { return bary[index(x, y)]; }
  /// True when a point at `depth` drawn on pixel (x, y) is not hidden by the
  /// surface (depth ≤ surface depth + bias).
  bool visible(int x, int y, double depth, double bias) const { return depth <= this->depth[index(x, y)] + bias; }
};

/// Z-buffered rasterisation of a triangle mesh at pixel centres (on equal
/// depth the earlier triangle wins); triangles with a corner behind a
/// perspective camera are skipped (no near-plane clipping).
GBuffer rasterize(const std::vector<Vec3>& positions, const std::vector<Tri>& triangles, const Camera& camera);

struct RenderResult {
  Image color;      ///< linear RGB, background dark grey
  GBuffer gbuffer;  ///< face indices into the mesh's triangles
  Camera camera;
};

/// Renders `mesh` textured with `atlas` (linear RGB or grey; one image or
/// UDIM tiles).
RenderResult render(const UVMesh& mesh, const TiledAtlas& atlas, const RenderOptions& options);
RenderResult render(const UVMesh& mesh, const Image& atlas, const RenderOptions& options);

/// render(mesh, atlas, options).color.
Image render_textured(const UVMesh& mesh, const TiledAtlas& atlas, const RenderOptions& options);
Image render_textured(const UVMesh& mesh, const Image& atlas, const RenderOptions& options);

// --- Drawing on a rendered image (overlays) -----------------------------------

using LinearRgb = std::array<float, 3>;  ///< linear RGB

/// Linear RGB of an 8-bit sRGB colour.
LinearRgb rgb_from_srgb8(const std::array<unsigned char, 3>& c);

/// Where an overlay may draw: the image, its G-buffer and camera, and the
/// depth bias (scene units) that keeps marks on the surface visible.
struct Canvas {
  Image& image;
  const GBuffer& gbuffer;
  const Camera& camera;
  double depth_bias = 0.0;
  bool depth_test = true;

  /// Sets pixel (x, y) when inside and not hidden at `depth`.
  void plot(int x, int y, double depth, const LinearRgb& color);
  /// The 3D segment a–b, one pixel wide, depth-tested along its length
  /// (skipped when an end is behind a perspective camera).
  void line(const Vec3& a, const Vec3& b, const LinearRgb& color);
  /// A filled disc of `radius` pixels centred on the projection of `p`, with
  /// a dark one-pixel rim, depth-tested at p's depth.
  void disc(const Vec3& p, double radius, const LinearRgb& color);
  /// An arrow from p to p + d with a head; drawn only when p is visible
  /// (the shaft itself is not depth-tested: it leaves the surface).
  void arrow(const Vec3& p, const Vec3& d, const LinearRgb& color);
};

/// Tiles `images` row-major in a near-square grid (columns = ⌈√n⌉) of cells
/// as large as the largest image, separated by `gap` pixels of background,
/// each image at its cell's top-left; `labels` (same count, may be empty)
/// are written in the cells' corners in a small digit font (digits and '-').
Image contact_sheet(const std::vector<Image>& images, const std::vector<std::string>& labels, int gap = 4);

}  // namespace fluidtex
