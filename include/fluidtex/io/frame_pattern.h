/// @file frame_pattern.h
/// @brief Frame-numbered file patterns and frame ranges, as used by render
/// farms and DCCs: `name.####.ply` (zero padded to the number of #),
/// `name.%04d.ply` (printf style, `%d` unpadded), `name.$F4.ply` / `name.$F.ply`
/// (Houdini style). Ranges: `1-120`, `1-120x2`, `7`, and comma lists of those.
///
/// A pattern may also hold the UDIM token `<UDIM>` (Mari, Houdini and
/// Blender write it so): one frame is then several files, one per texture
/// tile, the token replaced by the tile's four-digit number (1001, 1002, …).
#pragma once

#include <string>
#include <vector>

namespace fluidtex {

/// The UDIM tile token of a pattern.
inline constexpr const char* kUdimToken = "<UDIM>";

/// Limits on what a pattern or range may ask for.
inline constexpr int kMaxFrameWidth = 10;         ///< digits of a padded frame number (an int has at most 10)
inline constexpr long long kMaxFrames = 1000000;  ///< frames in one range

class FramePattern {
 public:
  /// Parses a pattern; throws InputError when it has no frame token, more
  /// than one, or a width over kMaxFrameWidth, or more than one UDIM token
  /// or one in a folder.
  explicit FramePattern(const std::string& pattern);

  /// The path of frame `frame` (negative frames get a leading '-'); with a
  /// UDIM token, the token stays (the name of every tile of the frame).
  std::string path(int frame) const;

  /// The path of tile `udim` (1001, …) of frame `frame`: path(frame) with
  /// the UDIM token replaced; path(frame) when the pattern has none.
  std::string path(int frame, int udim) const;

  /// The file that every written frame has: path(frame), or its tile 1001.
  std::string first_file(int frame) const { return path(frame, 1001); }

  /// The UDIM numbers of frame `frame`'s tiles on disk, ascending (empty
  /// when the pattern has no UDIM token).
  std::vector<int> udims(int frame) const;

  /// Every file of frame `frame`: path(frame), or each of its tiles on disk.
  std::vector<std::string> files(int frame) const;

  bool has_udim() const { return has_udim_; }
  /// Frames whose files (with a UDIM token: whose tile 1001) exist on disk, ascending. A file matches when the
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
  bool has_udim_ = false;
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
