#include "fluidtex/scenes/example.h"

#include "fluidtex/io/image_io.h"
#include "fluidtex/scenes/exemplar_gen.h"
#include "fluidtex/scenes/scenes.h"

namespace fluidtex {

namespace {

std::string listed(const std::string& lead, const std::vector<std::string>& names) {
  std::string text = lead;
  for (std::size_t i = 0; i < names.size(); ++i) text += (i == 0 ? "" : ", ") + names[i];
  return text;
}

}  // namespace

const char* ExampleRequest::scene_help() {
  static const std::string help = listed("Scene: ", scene_names());
  return help.c_str();
}

const char* ExampleRequest::exemplar_help() {
  static const std::string help = listed("Also write a procedural exemplar OUT/NAME.png: ", exemplar_names());
  return help.c_str();
}

ExampleFiles write_example(const ExampleRequest& request) {
  ExampleFiles files;
  files.frame_pattern = write_scene(request.scene, request.dir, request.scene_options);
  if (!request.exemplar.empty()) {
    files.exemplar = request.dir + "/" + request.exemplar + ".png";
    write_image(files.exemplar, make_exemplar(request.exemplar, request.exemplar_pixels, request.seed));
  }
  return files;
}

}  // namespace fluidtex
