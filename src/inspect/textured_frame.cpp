#include "fluidtex/inspect/textured_frame.h"

#include <filesystem>
#include <utility>

#include "fluidtex/io/frame_pattern.h"
#include "fluidtex/io/image_io.h"
#include "fluidtex/io/uv_mesh_io.h"
#include "fluidtex/util/error.h"

namespace fluidtex {

TexturedFrame::TexturedFrame(UVMesh m, Image a) : mesh(std::move(m)), atlas(std::move(a)) {
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
    for (int c = 0; c < atlas.channels; ++c) out[c] = 0.0f;
    return;
  }
  const Tri& t = mesh.uv_triangles[s.face];
  const Vec2 uv = interpolate(mesh.uvs, t, s.bary);
  sample_bilinear(atlas, u_to_px(uv.x(), atlas.width), v_to_py(uv.y(), atlas.height), out);
}

TexturedFrame read_run_frame(const std::string& atlas_pattern, const std::string& mesh_pattern, int frame) {
  const std::string atlas_path = FramePattern(atlas_pattern).path(frame);
  const std::string mesh_path = FramePattern(mesh_pattern).path(frame);
  if (!std::filesystem::exists(atlas_path))
    throw InputError(atlas_path, "missing: the run has no atlas for frame " + std::to_string(frame));
  if (!std::filesystem::exists(mesh_path))
    throw InputError(mesh_path, "missing: the run has no UV mesh for frame " + std::to_string(frame));
  Image atlas = read_image(atlas_path, kMaxAtlasPixels);
  // Colours are looked up into fixed buffers of kMaxLookupChannels.
  if (atlas.channels > kMaxLookupChannels) {
    throw InputError(atlas_path, std::to_string(atlas.channels) + " channels (a fluidtex atlas has at most " +
                                     std::to_string(kMaxLookupChannels) + ")");
  }
  return TexturedFrame(read_uv_mesh(mesh_path), std::move(atlas));
}

}  // namespace fluidtex
