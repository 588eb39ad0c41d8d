/// @file atlas.h
/// @brief The per-frame texture atlas of the whole surface (Gagnon et al.
/// 2019, Sec. 6.4: "All the pixels are computed on a texture atlas"; the
/// mapping uses Lévy et al. 2002). Since every frame is an independent mesh,
/// every frame gets its own atlas.
///
/// Charts: region growing from the lowest unassigned face over faces whose
/// normal stays within a cone of the seed's normal, kept a topological disk
/// (disk_region.h) and bounded in size; each chart is flattened with LSCM
/// (metric: uv area = 3D area), turned to its principal axes, scaled to one
/// common texel density (world units per texel, so detail is even across the
/// surface) and packed by shape (a horizon per column of cells, four
/// rotations: Lévy et al. 2002, Sec. 5) into a square of `size` texels with a
/// gutter between charts. A chart LSCM cannot flatten, that it stretches
/// beyond `max_stretch` or that covers less than `min_fill` of its bounding
/// box is cut in two across its long side first, and its pieces tested
/// again. The density is the largest that fits, or the one asked for
/// (`texel_density`) in the smallest square that holds it.
///
/// UDIM tiles: at a given density, charts that one `size` square cannot
/// hold go to further tiles of that size (up to `max_tiles`), each chart
/// into the first tile with room, largest first. Tile t covers uv
/// [t mod 10, t mod 10 + 1) × [⌊t/10⌋, ⌊t/10⌋ + 1) and is UDIM 1001 + t, as
/// Mari, Houdini and Blender number them.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "fluidtex/geometry/surface.h"
#include "fluidtex/geometry/uv_mesh.h"
#include "fluidtex/util/options.h"

namespace fluidtex {

struct AtlasOptions {
  int size = 2048;  ///< atlas width = height, texels (with texel_density: the largest)
  /// --texel-density: texels per scene unit, each frame's atlas the smallest
  /// square, a multiple of 64 texels up to `size`, that holds the charts at
  /// it; unset: the densest the `size` square holds.
  std::optional<double> texel_density;
  int gutter = 4;                      ///< empty texels around each chart (filled by dilation)
  int max_tiles = 1;                   ///< UDIM tiles a frame may take with texel_density (at most kMaxUdimTiles)
  double normal_cone = 0.85;           ///< faces join a chart while N_f·N_seed > this
  std::size_t max_chart_faces = 5000;  ///< chart size bound (LSCM cost, distortion)
  double max_stretch = 1.5;            ///< charts with a larger mean area stretch are cut in two
  double min_fill = 0.5;               ///< charts covering less of their bounding box are cut in two (packing)...
  std::size_t min_fill_faces = 64;     ///< ...unless they have at most this many faces

  /// The fields a user sets, as f(OptionInfo, field) (util/options.h).
  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    f(OptionInfo{.name = "atlas-size",
                 .help = "Atlas width and height in texels (with --texel-density: the largest a frame may take)",
                 .bounds = between(16, 32768)},
      o.size);
    f(OptionInfo{.name = "texel-density",
                 .help = "Atlas texels per scene unit: each frame's atlas is the smallest square, a multiple of 64 "
                         "texels up to --atlas-size, that holds the surface at this density, or with <UDIM> in "
                         "--atlas as many --atlas-size tiles as it needs (auto: the densest that --atlas-size holds)",
                 .bounds = between(1e-9, 1e9)},
      o.texel_density);
    f(OptionInfo{.name = "gutter", .help = "Texels between charts, filled by dilation", .bounds = between(1, 64)},
      o.gutter);
  }

  void validate() const;  ///< InputError for a bad value
};

/// The most UDIM tiles a frame's atlas may take (1001–1100: ten rows of ten).
inline constexpr int kMaxUdimTiles = 100;

/// The UDIM number of tile `tile` (0-based) and the uv of its lower-left corner.
inline int udim_number(int tile) { return 1001 + tile; }
inline Vec2 udim_offset(int tile) { return {static_cast<double>(tile % 10), static_cast<double>(tile / 10)}; }

struct Chart {
  std::vector<int> faces;        ///< surface faces, in growth order
  int tile = 0;                  ///< the UDIM tile it lies in (0: 1001)
  Eigen::Vector2i origin{0, 0};  ///< lower-left texel of its rectangle (gutter included)
  Eigen::Vector2i extent{0, 0};  ///< rectangle size in texels (gutter included)
  double area3 = 0.0;            ///< 3D area
  double stretch = 1.0;          ///< area-weighted mean of max(a_uv/a_3d, a_3d/a_uv) (1 = no area distortion)
};

struct Atlas {
  int size = 0;                  ///< width = height of each tile, texels
  int tiles = 1;                 ///< UDIM tiles, 1001 to 1000 + tiles
  double texels_per_unit = 0.0;  ///< texel density (texels per scene unit)
  std::vector<Chart> charts;
  std::vector<int> face_chart;                 ///< chart of each surface face
  std::vector<std::array<Vec2, 3>> corner_px;  ///< per face, corner positions in its tile's texels (x right, y down)
  double packing_efficiency = 0.0;             ///< chart area / area of all tiles
  int failed_charts = 0;                       ///< charts cut again (LSCM failed or stretched too much)
};

/// Builds the atlas of `surface`.
Atlas build_atlas(const SurfaceIndex& surface, const AtlasOptions& options);

/// The UV mesh of the frame: positions, vertex normals, triangles and per
/// corner atlas uv (v up) in [0,1]² for tile 1001, in UDIM space for the
/// others, shared where corners share a vertex and a chart.
UVMesh atlas_uv_mesh(const SurfaceIndex& surface, const Atlas& atlas);

}  // namespace fluidtex
