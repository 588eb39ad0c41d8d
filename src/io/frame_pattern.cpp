#include "fluidtex/io/frame_pattern.h"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <regex>
#include <set>
#include <string_view>

#include "fluidtex/util/error.h"

namespace fluidtex {

namespace {

struct Token {
  std::size_t pos = std::string::npos;
  std::size_t len = 0;
  int width = 1;
};

/// The digit count a "%0Nd" or "$FN" token asks for (1 when none): at most
/// kMaxFrameWidth, since a frame number is an int.
int token_width(const std::string& pattern, const std::string& digits) {
  if (digits.empty()) return 1;
  int width = 0;
  const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), width);
  if (r.ec != std::errc() || width > kMaxFrameWidth) {
    throw InputError(pattern, "frame number width " + digits + " is too large (at most " +
                                  std::to_string(kMaxFrameWidth) + " digits)");
  }
  return std::max(1, width);
}

// Finds every frame token: a run of '#', printf "%d"/"%0Nd"/"%Nd", Houdini "$F"/"$FN".
std::vector<Token> find_tokens(const std::string& s) {
  std::vector<Token> tokens;
  for (std::size_t i = 0; i < s.size();) {
    if (s[i] == '#') {
      std::size_t j = i;
      while (j < s.size() && s[j] == '#') ++j;
      tokens.push_back({i, j - i, static_cast<int>(j - i)});
      i = j;
    } else if (s[i] == '%') {
      std::size_t j = i + 1;
      while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
      if (j < s.size() && s[j] == 'd') {
        const int width = token_width(s, s.substr(i + 1, j - i - 1));
        tokens.push_back({i, j + 1 - i, width});
        i = j + 1;
      } else {
        ++i;
      }
    } else if (s[i] == '$' && i + 1 < s.size() && s[i + 1] == 'F') {
      std::size_t j = i + 2;
      while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
      const int width = token_width(s, s.substr(i + 2, j - i - 2));
      tokens.push_back({i, j - i, width});
      i = j;
    } else {
      ++i;
    }
  }
  return tokens;
}

int parse_int(const std::string& text, const std::string& whole) {
  int value = 0;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(first, last, value);
  if (text.empty() || ec != std::errc() || ptr != last) {
    throw InputError("", "malformed frame range '" + whole + "' (expected e.g. 1-120 or 1-120x2)");
  }
  return value;
}

}  // namespace

FramePattern::FramePattern(const std::string& pattern) : pattern_(pattern) {
  // Only the file name may carry the token; folders are taken literally.
  const auto tokens = find_tokens(pattern);
  if (tokens.empty()) {
    throw InputError(pattern, "no frame number token in the pattern (use ####, %04d or $F4)");
  }
  if (tokens.size() > 1) {
    throw InputError(pattern, "more than one frame number token in the pattern");
  }
  prefix_ = pattern.substr(0, tokens[0].pos);
  suffix_ = pattern.substr(tokens[0].pos + tokens[0].len);
  width_ = tokens[0].width;
  if (suffix_.find('/') != std::string::npos) {
    throw InputError(pattern, "the frame number token must be in the file name, not in a folder");
  }
  const std::size_t udim = pattern.find(kUdimToken);
  has_udim_ = udim != std::string::npos;
  if (has_udim_ && pattern.find(kUdimToken, udim + 1) != std::string::npos)
    throw InputError(pattern, "more than one <UDIM> token in the pattern");
  if (has_udim_ && pattern.find('/', udim) != std::string::npos)
    throw InputError(pattern, "the <UDIM> token must be in the file name, not in a folder");
}

std::string FramePattern::path(int frame, int udim) const {
  std::string p = path(frame);
  if (has_udim_) p.replace(p.find(kUdimToken), std::string_view(kUdimToken).size(), std::to_string(udim));
  return p;
}

std::vector<int> FramePattern::udims(int frame) const {
  namespace fs = std::filesystem;
  if (!has_udim_) return {};
  const fs::path p(path(frame));
  const std::string name = p.filename().string();
  const std::size_t at = name.find(kUdimToken);
  const std::string before = name.substr(0, at), after = name.substr(at + std::string_view(kUdimToken).size());
  std::set<int> tiles;
  std::error_code ec;
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string file = entry.path().filename().string();
    if (file.size() != before.size() + 4 + after.size() || !file.starts_with(before) || !file.ends_with(after))
      continue;
    const std::string digits = file.substr(before.size(), 4);
    int udim = 0;
    const auto [ptr, perr] = std::from_chars(digits.data(), digits.data() + 4, udim);
    if (perr == std::errc() && ptr == digits.data() + 4 && udim >= 1001 && udim <= 9999) tiles.insert(udim);
  }
  return {tiles.begin(), tiles.end()};
}

std::vector<std::string> FramePattern::files(int frame) const {
  if (!has_udim_) return {path(frame)};
  std::vector<std::string> out;
  for (int udim : udims(frame)) out.push_back(path(frame, udim));
  return out;
}

bool FramePattern::has_token(const std::string& s) { return !find_tokens(s).empty(); }

std::string FramePattern::path(int frame) const {
  std::string digits = std::to_string(frame < 0 ? -static_cast<long>(frame) : frame);
  if (static_cast<int>(digits.size()) < width_) digits.insert(0, width_ - digits.size(), '0');
  return prefix_ + (frame < 0 ? "-" : "") + digits + suffix_;
}

std::vector<int> FramePattern::discover() const {
  namespace fs = std::filesystem;
  if (has_udim_) {  // the frames whose tile 1001 exists
    auto first_tile = [](std::string s) {
      if (const std::size_t at = s.find(kUdimToken); at != std::string::npos)
        s.replace(at, std::string_view(kUdimToken).size(), "1001");
      return s;
    };
    FramePattern tile(*this);
    tile.prefix_ = first_tile(prefix_), tile.suffix_ = first_tile(suffix_), tile.has_udim_ = false;
    return tile.discover();
  }
  const fs::path prefix_path(prefix_);
  fs::path dir = prefix_path.parent_path();
  // prefix "dir/name." -> folder "dir", file prefix "name."; prefix "dir/" -> file prefix "".
  std::string file_prefix =
      prefix_.substr(prefix_.find_last_of('/') == std::string::npos ? 0 : prefix_.find_last_of('/') + 1);
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return {};
  std::set<int> frames;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= file_prefix.size() + suffix_.size()) continue;
    if (name.compare(0, file_prefix.size(), file_prefix) != 0) continue;
    if (name.compare(name.size() - suffix_.size(), suffix_.size(), suffix_) != 0) continue;
    std::string middle = name.substr(file_prefix.size(), name.size() - file_prefix.size() - suffix_.size());
    bool negative = !middle.empty() && middle[0] == '-';
    if (negative) middle.erase(0, 1);
    if (middle.empty() || !std::all_of(middle.begin(), middle.end(),
                                       [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) {
      continue;
    }
    if (static_cast<int>(middle.size()) < width_) continue;
    // A padded pattern writes exactly `width_` digits unless the number needs more.
    if (static_cast<int>(middle.size()) > width_ && middle[0] == '0') continue;
    if (width_ == 1 && middle.size() > 1 && middle[0] == '0') continue;
    int value = 0;
    auto [ptr, perr] = std::from_chars(middle.data(), middle.data() + middle.size(), value);
    if (perr != std::errc() || ptr != middle.data() + middle.size()) continue;
    // Not only regular files: a folder, FIFO or dangling link named like a
    // frame is a frame that cannot be read (an error when it is loaded), not
    // a gap that would make dt span two frames.
    frames.insert(negative ? -value : value);
  }
  return {frames.begin(), frames.end()};
}

std::vector<int> parse_frame_range(const std::string& text) {
  if (text.empty()) throw InputError("", "empty frame range");
  std::set<int> frames;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t comma = text.find(',', start);
    if (comma == std::string::npos) comma = text.size();
    const std::string part = text.substr(start, comma - start);
    if (part.empty()) throw InputError("", "malformed frame range '" + text + "'");
    int step = 1;
    std::string span = part;
    if (const auto x = part.find('x'); x != std::string::npos) {
      step = parse_int(part.substr(x + 1), text);
      span = part.substr(0, x);
      if (step < 1) throw InputError("", "frame range '" + text + "' has a step below 1");
    }
    // A '-' after the first character separates first and last (a leading '-' is a sign).
    const auto dash = span.find('-', 1);
    const int first = parse_int(span.substr(0, dash), text);
    const int last = dash == std::string::npos ? first : parse_int(span.substr(dash + 1), text);
    if (last < first) throw InputError("", "frame range '" + text + "' ends before it starts");
    const long long count = (static_cast<long long>(last) - first) / step + 1;
    if (count + static_cast<long long>(frames.size()) > kMaxFrames) {
      throw InputError("", "frame range '" + text + "' has more than " + std::to_string(kMaxFrames) + " frames");
    }
    for (long f = first; f <= last; f += step) frames.insert(static_cast<int>(f));
    start = comma + 1;
  }
  return {frames.begin(), frames.end()};
}

std::string format_frame_range(const std::vector<int>& frames) {
  std::string text;
  std::size_t i = 0;
  while (i < frames.size()) {
    // The longest run of a constant step from frames[i] (a lone frame when
    // the next step differs from the one after it).
    std::size_t j = i + 1;
    if (j < frames.size()) {
      const long long step = static_cast<long long>(frames[j]) - frames[i];
      while (j + 1 < frames.size() && static_cast<long long>(frames[j + 1]) - frames[j] == step) ++j;
      if (j == i + 1 && step != 1) j = i;  // two frames with a gap: written as two items
    } else {
      j = i;
    }
    if (!text.empty()) text += ',';
    text += std::to_string(frames[i]);
    if (j > i) {
      text += '-' + std::to_string(frames[j]);
      const long long step = static_cast<long long>(frames[i + 1]) - frames[i];
      if (step != 1) text += 'x' + std::to_string(step);
    }
    i = j + 1;
  }
  return text;
}

}  // namespace fluidtex
