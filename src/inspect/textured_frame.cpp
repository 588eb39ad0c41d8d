#include "fluidtex/inspect/textured_frame.h"

#include <filesystem>
#include <utility>

#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/io/image_io.h"
#include "fluidtex/io/uv_mesh_io.h"
#include "fluidtex/util/error.h"

namespace fluidtex {

TexturedFrame::TexturedFrame(UVMesh m, TiledAtlas a) : mesh(std::move(m)), atlas(std::move(a)) {
  auto g = std::make_unique<FrameMesh>();
  g->positions = mesh.positions;
  g->triangles = mesh.triangles;
  g->velocities.assign(mesh.positions.size(), Vec3::Zero());
  geometry = std::move(g);  // on the heap: the index keeps its address when the frame is moved
  surface = std::make_unique<SurfaceIndex>(*geometry);
}

void TexturedFrame::color_at(const Vec3& p, float* out) const {
  const SurfacePoint s = surface->closest_point(p);
  if (!s.valid()) {
    for (int c = 0; c < atlas.first().channels; ++c) out[c] = 0.0f;
    return;
  }
  const Tri& t = mesh.uv_triangles[s.face];
  atlas.sample(interpolate(mesh.uvs, t, s.bary), out);
}

TiledAtlas read_frame_atlas(const std::string& atlas_pattern, int frame) {
  const FramePattern pattern(atlas_pattern);
  const std::string first = pattern.first_file(frame);
  if (!std::filesystem::exists(first))
    throw InputError(first, "missing: the run has no atlas for frame " + std::to_string(frame));
  TiledAtlas atlas;
  atlas.udim = pattern.has_udim();
  atlas.udims = atlas.udim ? pattern.udims(frame) : std::vector<int>{1001};
  for (int udim : atlas.udims) {
    const std::string path = pattern.path(frame, udim);
    Image tile = read_image(path, kMaxAtlasPixels);
    // Colours are looked up into fixed buffers of kMaxLookupChannels.
    if (tile.channels > kMaxLookupChannels) {
      throw InputError(path, std::to_string(tile.channels) + " channels (a fluidtex atlas has at most " +
                                 std::to_string(kMaxLookupChannels) + ")");
    }
    if (!atlas.tiles.empty() && tile.channels != atlas.first().channels) {
      throw InputError(path, std::to_string(tile.channels) + " channels, tile 1001 " +
                                 std::to_string(atlas.first().channels) + " (the tiles of one atlas share them)");
    }
    atlas.tiles.push_back(std::move(tile));
  }
  return atlas;
}

TexturedFrame read_run_frame(const std::string& atlas_pattern, const std::string& mesh_pattern, int frame) {
  const std::string mesh_path = FramePattern(mesh_pattern).path(frame);
  TiledAtlas atlas = read_frame_atlas(atlas_pattern, frame);
  if (!std::filesystem::exists(mesh_path))
    throw InputError(mesh_path, "missing: the run has no UV mesh for frame " + std::to_string(frame));
  return TexturedFrame(read_uv_mesh(mesh_path), std::move(atlas));
}

}  // namespace fluidtex
