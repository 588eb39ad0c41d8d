// The frame layers (job/frame_layers.h): each row is an option of the job or
// an --aov choice, a file of the job, and written with its encoding.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "fluidtex/job/frame_layers.h"
#include "fluidtex/job/job_layout.h"
#include "fluidtex/job/job_options.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/options.h"

namespace fluidtex {
namespace {

TEST(FrameLayers, EachLayerIsAnOptionOrAnAovChoiceAndAFileOfTheJob) {
  JobOptions o;
  o.input.pattern = "in/frame.####.ply";
  o.output.dir = "out";
  const std::vector<std::string> aov_choices = option_detail::split_choices(aov_layer_names());
  for (std::size_t i = 0; i < kFrameLayerCount; ++i) {
    const FrameLayer& layer = kFrameLayers[i];
    EXPECT_TRUE(o.layer_pattern(i).empty()) << layer.name << " is written by default";
    if (layer.option) {
      o.output.layer_patterns[i] = std::string("out/") + layer.name + ".####.exr";
    } else {
      EXPECT_NE(std::find(aov_choices.begin(), aov_choices.end(), layer.name), aov_choices.end()) << layer.name;
      o.synthesis.aov.push_back(layer.name);
    }
  }
  const std::vector<OptionRef> table = option_table(o);
  const std::vector<FrameOutput> outputs = labelled_frame_outputs(o);
  for (std::size_t i = 0; i < kFrameLayerCount; ++i) {
    const FrameLayer& layer = kFrameLayers[i];
    const std::string what = layer.option ? "--" + std::string(layer.option) : "--aov " + std::string(layer.name);
    const auto output =
        std::find_if(outputs.begin(), outputs.end(), [&](const FrameOutput& f) { return f.what == what; });
    ASSERT_NE(output, outputs.end()) << what;
    EXPECT_EQ(output->pattern, o.layer_pattern(i));
    if (!layer.option) {
      EXPECT_EQ(output->pattern, "out/aov/" + std::string(layer.name) + ".####.exr");
      continue;
    }
    const auto ref = std::find_if(table.begin(), table.end(),
                                  [&](const OptionRef& r) { return std::string(r.info.name) == layer.option; });
    ASSERT_NE(ref, table.end()) << layer.option;
    EXPECT_EQ(ref->info.role, OptionRole::OutputPath) << layer.option;
    EXPECT_EQ(ref->text(), o.output.layer_patterns[i]);
  }
}

TEST(FrameLayers, PatternsOtherThanExrAreRefusedNamingTheOption) {
  JobOptions o;
  o.output.dir = "out";
  for (std::size_t i = 0; i < kFrameLayerCount; ++i) {
    if (!kFrameLayers[i].option) continue;
    o.output.layer_patterns[i] = "out/map.####.png";
    try {
      (void)o.layer_pattern(i);
      ADD_FAILURE() << kFrameLayers[i].option << " took a .png pattern";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(kFrameLayers[i].option), std::string::npos) << e.what();
    }
    o.output.layer_patterns[i].clear();
  }
}

TEST(FrameLayers, DataLayersTakeTheAtlasSettingsWithoutColourSpace) {
  ImageWriteOptions atlas;
  atlas.depth = PixelDepth::Float;
  atlas.compression = ExrCompression::Dwaa;
  atlas.metadata = {{"fluidtex:frame", "7"}};
  for (const FrameLayer& layer : kFrameLayers) {
    const ImageWriteOptions write = layer_write_options(layer, atlas);
    EXPECT_EQ(write.channel_names, option_detail::split_choices(layer.channels)) << layer.name;
    switch (layer.pixels) {
      case LayerPixels::Data:
        EXPECT_TRUE(write.data) << layer.name;
        EXPECT_EQ(write.depth, PixelDepth::Float) << layer.name;
        EXPECT_EQ(write.compression, ExrCompression::Dwaa) << layer.name;
        EXPECT_EQ(write.metadata, atlas.metadata) << layer.name;
        break;
      case LayerPixels::Float:
        EXPECT_EQ(write.depth, PixelDepth::Float) << layer.name;
        EXPECT_TRUE(write.metadata.empty()) << layer.name;
        break;
      case LayerPixels::IdColour:
        EXPECT_EQ(write.depth, PixelDepth::Default) << layer.name;
        EXPECT_FALSE(write.data) << layer.name;
        break;
    }
  }
}

}  // namespace
}  // namespace fluidtex
