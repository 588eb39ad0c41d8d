/// @file frame_pattern.h
/// @brief Frame-numbered file patterns and frame ranges, as used by render
/// farms and DCCs: `name.####.ply` (zero padded to the number of #),
/// `name.%04d.ply` (printf style, `%d` unpadded), `name.$F4.ply` / `name.$F.ply`
/// (Houdini style). Ranges: `1-120`, `1-120x2`, `7`, and comma lists of those.
#pragma once

#include <string>
#include <vector>

namespace fluidtex {

/// Limits on what a pattern or range may ask for.
inline constexpr int kMaxFrameWidth = 10;         ///< digits of a padded frame number (an int has at most 10)
inline constexpr long long kMaxFrames = 1000000;  ///< frames in one range

class FramePattern {
 public:
  /// Parses a pattern; throws InputError when it has no frame token, more
  /// than one, or a width over kMaxFrameWidth.
  explicit FramePattern(const std::string& pattern);

  /// The path of frame `frame` (negative frames get a leading '-').
  std::string path(int frame) const;

  /// Frames whose files exist on disk, ascending. A file matches when the
  /// part in place of the token is an integer with at least `width()` digits
  /// (exactly width() when zero padded with more digits possible for large
  /// numbers, as printf does).
  std::vector<int> discover() const;

  const std::string& pattern() const { return pattern_; }
  const std::string& prefix() const { return prefix_; }
  const std::string& suffix() const { return suffix_; }
  int width() const { return width_; }  ///< minimum digits (1 = unpadded)

  /// True when `s` contains a frame token this class understands.
  static bool has_token(const std::string& s);

 private:
  std::string pattern_, prefix_, suffix_;
  int width_ = 1;
};

/// Parses `1-120`, `1-120x2`, `7`, `1-10,20-30x5`; throws InputError on
/// malformed text, an empty range (end < start), a step < 1 or more than
/// kMaxFrames frames. Ascending, without duplicates.
std::vector<int> parse_frame_range(const std::string& text);

/// The shortest text parse_frame_range reads back as `frames` (ascending,
/// without duplicates): runs of a constant step as `A-B` or `A-BxS`, joined
/// by commas ("1-48", "1-47x2", "1-10,12,20-30x5"); empty for no frames.
std::string format_frame_range(const std::vector<int>& frames);

}  // namespace fluidtex
