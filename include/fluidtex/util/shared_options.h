/// @file shared_options.h
/// @brief The options several commands share, declared once: `-o`, `-i`,
/// `--velocity-vdb`, `-e`, `--frames`, `--seed`, `--threads`, `--samples` and `--view` have
/// the same flag, bounds and record role in every command that takes them.
/// A command may say in its own words what the value is to it
/// (`with_help`); the rest of the entry stays this one.
#pragma once

#include "fluidtex/util/options.h"

namespace fluidtex::shared_options {

inline constexpr OptionInfo kOutput{
    .name = "output", .help = "Output folder", .alias = "-o", .role = OptionRole::OutputPath};
inline constexpr OptionInfo kInput{.name = "input",
                                   .help = "Input frame pattern: mesh.####.ply, mesh.%04d.ply or mesh.$F4.ply",
                                   .alias = "-i",
                                   .role = OptionRole::InputPath};
inline constexpr OptionInfo kVelocityVdb{.name = "velocity-vdb",
                                         .help =
                                             "Take each frame's velocities from this VDB frame pattern (same frame "
                                             "numbers), sampled at the mesh's vertices",
                                         .role = OptionRole::InputPath};
inline constexpr OptionInfo kExemplar{
    .name = "exemplar", .help = "Exemplar texture", .alias = "-e", .role = OptionRole::InputPath};
/// A frame range: "7-12", "1-120x2"; empty = all of them.
inline constexpr OptionInfo kFrames{
    .name = "frames", .help = "Frames to use, e.g. 1-120 or 1-120x2 (default: all found)", .role = OptionRole::Free};
inline constexpr OptionInfo kSeed{.name = "seed", .help = "Random seed"};
inline constexpr OptionInfo kThreads{.name = "threads",
                                     .help = "Threads in all, image reading and writing included (0 = all cores)",
                                     .bounds = between(0, 4096),
                                     .role = OptionRole::Free};
/// Surface or image sample points per frame (eval, compare).
inline constexpr OptionInfo kSamples{
    .name = "samples", .help = "Sample points per frame", .bounds = between(100, 10000000)};
/// The orthographic view of a render (inspect/render.h's View).
inline constexpr OptionInfo kView{.name = "view", .help = "Orthographic view along an axis: top, front, side"};

/// `info` with the help line of the command that takes it.
constexpr OptionInfo with_help(OptionInfo info, const char* help) {
  info.help = help;
  return info;
}

/// `info` as a command's required option.
constexpr OptionInfo required(OptionInfo info, const char* help) {
  info.help = help;
  info.required = true;
  return info;
}

}  // namespace fluidtex::shared_options
