/// @file example.h
/// @brief `fluidtex gen`: an example scene (scenes.h) and, on request, a
/// procedural exemplar (exemplar_gen.h) written into one folder.
#pragma once

#include <cstdint>
#include <string>

#include "fluidtex/scenes/scene_options.h"
#include "fluidtex/util/options.h"
#include "fluidtex/util/shared_options.h"

namespace fluidtex {

struct ExampleRequest {
  std::string scene;           ///< one of scene_names()
  std::string dir;             ///< -o: where the frames (and the exemplar) go
  SceneOptions scene_options;  ///< frames, rate, density, format
  std::string exemplar;        ///< --exemplar: one of exemplar_names(); empty = none
  int exemplar_pixels = 512;   ///< the exemplar's width and height in pixels
  std::uint64_t seed = 1;      ///< the exemplar's seed

  /// "Scene: NAME, NAME, ..." and "Also write ...: NAME, ...": the help
  /// lines that list the generators.
  static const char* scene_help();
  static const char* exemplar_help();

  /// The options of `gen` as f(OptionInfo, field) (util/options.h).
  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    using namespace shared_options;
    f(OptionInfo{.name = "scene", .help = scene_help(), .positional = true, .required = true}, o.scene);
    f(required(kOutput, "Output folder (frames are SCENE.####.ply or .vdb)"), o.dir);
    SceneOptions::for_each_option(o.scene_options, f);
    f(OptionInfo{.name = "exemplar", .help = exemplar_help()}, o.exemplar);
    f(
        OptionInfo{
            .name = "exemplar-pixels", .help = "Width and height of the exemplar in pixels", .bounds = at_least(8)},
        o.exemplar_pixels);
    f(with_help(kSeed, "Seed of the exemplar"), o.seed);
  }
};

/// What write_example wrote.
struct ExampleFiles {
  std::string frame_pattern;  ///< the scene's frames
  std::string exemplar;       ///< the exemplar's path; empty when none was asked for
};

/// Writes the scene's frames to request.dir (write_scene) and the exemplar
/// to request.dir/NAME.png. InputError for an unknown scene or exemplar or
/// an invalid option.
ExampleFiles write_example(const ExampleRequest& request);

}  // namespace fluidtex
