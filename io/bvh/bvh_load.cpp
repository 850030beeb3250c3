#include "io/bvh/bvh_load.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "io/files/load_error.h"

namespace sweepd::io {

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

bool is_blank(std::string_view line) { return std::all_of(line.begin(), line.end(), is_space); }

// Whole-token number parsing (std::from_chars has no leading '+'; BVH writers rarely emit one).
template <class Number>
bool parse_number(std::string_view text, Number& out) {
  if (text.size() > 1 && text.front() == '+' && text[1] != '-' && text[1] != '+') {
    text.remove_prefix(1);
  }
  if (text.empty()) return false;
  const char* end = text.data() + text.size();
  auto [stop, error] = std::from_chars(text.data(), end, out);
  return error == std::errc() && stop == end;
}

std::string in_quotes(std::string_view text) { return "'" + std::string(text) + "'"; }

struct Token {
  std::string_view text;  // empty at the end of the file
  int line = 0;
};

std::string describe(const Token& token) {
  return token.text.empty() ? "the end of the file" : in_quotes(token.text);
}

// Walks the text token by token (the hierarchy) or line by line (the data rows), counting lines.
class TextCursor {
 public:
  explicit TextCursor(std::string_view text) : text_(text) {}

  // The next whitespace-separated token; at the end of the file an empty token on the last line.
  Token next() {
    while (pos_ < text_.size() && (is_space(text_[pos_]) || text_[pos_] == '\n')) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    if (pos_ == text_.size()) return {{}, last_token_line_};
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_]) && text_[pos_] != '\n') ++pos_;
    last_token_line_ = line_;
    return {text_.substr(start, pos_ - start), line_};
  }

  std::size_t remaining() const { return text_.size() - std::min(pos_, text_.size()); }

  Token peek() const {
    TextCursor copy = *this;
    return copy.next();
  }

  // The rest of the current line without its line break; false at the end of the file.
  bool next_line(std::string_view& line, int& line_number) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    line = text_.substr(pos_, end - pos_);
    line_number = line_;
    pos_ = end + 1;
    ++line_;
    return true;
  }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  int line_ = 1;
  int last_token_line_ = 1;
};

// One "{ ... }" block being read: a joint's, or the End Site's inside it.
struct OpenBlock {
  int joint = 0;
  bool end_site = false;
  int line = 0;  // where the block's keyword is
  bool has_offset = false;
  bool has_channels = false;
  bool has_end_site = false;
};

class BvhParser {
 public:
  BvhParser(std::string_view text, const std::filesystem::path& source, const BvhOptions& options)
      : cursor_(text), source_(source), scale_(options.length_scale), up_(options.up) {}

  motion::Clip parse() {
    if (!(std::isfinite(scale_) && scale_ > 0.0f)) {
      throw LoadError(source_,
                      "length_scale must be finite and > 0, got " + std::to_string(scale_));
    }
    parse_hierarchy();
    parse_motion_header();
    parse_rows();
    if ((up_ ? *up_ : motion::detect_up_axis(clip_)) == motion::UpAxis::kZ)
      motion::turn_z_up_to_y_up(clip_);
    return std::move(clip_);
  }

 private:
  [[noreturn]] void fail(int line, const std::string& reason) const {
    throw LoadError(source_, reason, line);
  }

  std::string block_name(const OpenBlock& block) const {
    const std::string joint = "joint " + in_quotes(clip_.joints[block.joint].name);
    return block.end_site ? "the End Site of " + joint : joint;
  }

  void parse_hierarchy() {
    const Token first = cursor_.next();
    if (first.text.empty()) fail(first.line, "the file is empty; a BVH file starts with HIERARCHY");
    if (first.text != "HIERARCHY") {
      fail(first.line, "missing HIERARCHY: the file starts with " + describe(first));
    }
    for (;;) {
      const Token token = cursor_.next();
      const bool empty = clip_.joints.empty();
      if (token.text == "ROOT") {
        parse_root(token);
      } else if (token.text == "MOTION") {
        if (empty) fail(token.line, "empty hierarchy: no ROOT joint before MOTION");
        return;
      } else if (token.text.empty()) {
        fail(token.line, empty ? "missing ROOT: the file ends after HIERARCHY"
                               : "missing MOTION: the file ends after the hierarchy");
      } else if (token.text == "}") {
        fail(token.line, "unbalanced braces: '}' without a matching '{'");
      } else {
        fail(token.line, (empty ? "missing ROOT: expected ROOT after HIERARCHY, found "
                                : "missing MOTION: expected ROOT or MOTION after the "
                                  "hierarchy, found ") +
                             describe(token));
      }
    }
  }

  // Reads "ROOT name { ... }" and everything nested in it, without recursion.
  void parse_root(const Token& root) {
    std::vector<OpenBlock> open;
    open_joint(root, -1, open);
    while (!open.empty()) {
      const Token token = cursor_.next();
      const OpenBlock block = open.back();
      if (token.text.empty() || token.text == "MOTION" || token.text == "ROOT") {
        fail(token.line, "unbalanced braces: the block of " + block_name(block) + " (line " +
                             std::to_string(block.line) + ") is not closed before " +
                             describe(token));
      } else if (token.text == "}") {
        if (!block.has_offset) fail(token.line, block_name(block) + " has no OFFSET");
        open.pop_back();
      } else if (token.text == "OFFSET") {
        if (block.has_offset) fail(token.line, block_name(block) + " has a second OFFSET");
        const glm::vec3 offset = read_offset(block) * scale_;
        motion::ClipJoint& joint = clip_.joints[block.joint];
        if (block.end_site) {
          joint.end_site = offset;
        } else {
          joint.offset = offset;
        }
        open.back().has_offset = true;
      } else if (token.text == "CHANNELS") {
        if (block.end_site) fail(token.line, "an End Site cannot have CHANNELS");
        if (block.has_channels) fail(token.line, block_name(block) + " has a second CHANNELS");
        read_channels(block);
        open.back().has_channels = true;
      } else if (token.text == "JOINT") {
        if (block.end_site) fail(token.line, "an End Site cannot contain a JOINT");
        open_joint(token, block.joint, open);
      } else if (token.text == "End") {
        const Token site = cursor_.next();
        if (site.text != "Site")
          fail(site.line, "expected 'Site' after 'End', found " + describe(site));
        if (block.end_site) fail(token.line, "an End Site cannot contain an End Site");
        if (block.has_end_site) fail(token.line, block_name(block) + " has a second End Site");
        expect_open_brace("End Site");
        open.back().has_end_site = true;
        open.push_back({.joint = block.joint, .end_site = true, .line = token.line});
      } else {
        fail(token.line, "unknown keyword " + describe(token) + " in " + block_name(block));
      }
    }
  }

  void expect_open_brace(const std::string& after) {
    const Token brace = cursor_.next();
    if (brace.text != "{")
      fail(brace.line, "expected '{' after " + after + ", found " + describe(brace));
  }

  // keyword is ROOT or JOINT; the name is the rest of its line up to any '{'.
  void open_joint(const Token& keyword, int parent, std::vector<OpenBlock>& open) {
    std::string name;
    for (Token next = cursor_.peek();
         !next.text.empty() && next.line == keyword.line && next.text != "{";
         next = cursor_.peek()) {
      if (!name.empty()) name += ' ';
      name += cursor_.next().text;
    }
    if (name.empty()) fail(keyword.line, std::string(keyword.text) + " has no name");
    expect_open_brace(std::string(keyword.text) + " " + name);

    const int index = static_cast<int>(clip_.joints.size());
    const auto [first, inserted] = joint_by_name_.emplace(name, index);
    if (!inserted) {
      clip_.warnings.push_back("line " + std::to_string(keyword.line) + ": duplicate joint name " +
                               in_quotes(name) + " (also joint " + std::to_string(first->second) +
                               ")");
    }
    motion::ClipJoint& joint = clip_.joints.emplace_back();
    joint.name = std::move(name);
    joint.parent = parent;
    joint.channel_offset = clip_.channel_count;
    open.push_back({.joint = index, .end_site = false, .line = keyword.line});
  }

  glm::vec3 read_offset(const OpenBlock& block) {
    glm::vec3 offset(0.0f);
    for (int axis = 0; axis < 3; ++axis) {
      const Token value = cursor_.next();
      if (!parse_number(value.text, offset[axis])) {
        fail(value.line,
             "OFFSET of " + block_name(block) + " needs 3 numbers, found " + describe(value));
      }
      if (!std::isfinite(offset[axis])) {
        fail(value.line, "OFFSET of " + block_name(block) + " is not finite: " + describe(value));
      }
    }
    return offset;
  }

  void read_channels(const OpenBlock& block) {
    const Token count_token = cursor_.next();
    int count = 0;
    if (!parse_number(count_token.text, count) || count < 0) {
      fail(count_token.line, "CHANNELS count of " + block_name(block) +
                                 " is not a non-negative whole number: " + describe(count_token));
    }
    motion::ClipJoint& joint = clip_.joints[block.joint];
    joint.channel_offset = clip_.channel_count;
    for (int c = 0; c < count; ++c) {
      const Token name = cursor_.next();
      const std::optional<motion::Channel> channel = motion::channel_from_name(name.text);
      if (!channel) {
        fail(name.line, "bad channel name " + describe(name) + " (channel " +
                            std::to_string(c + 1) + " of " + std::to_string(count) + " of " +
                            block_name(block) +
                            "; expected Xposition, Yposition, Zposition, Xrotation, Yrotation "
                            "or Zrotation)");
      }
      joint.channels.push_back(*channel);
    }
    clip_.channel_count += count;
  }

  void parse_motion_header() {
    const Token frames = cursor_.next();
    if (frames.text != "Frames:") {
      fail(frames.line, "missing 'Frames:' after MOTION, found " + describe(frames));
    }
    const Token count = cursor_.next();
    if (!parse_number(count.text, clip_.header_frame_count) || clip_.header_frame_count < 0) {
      fail(count.line, "'Frames:' count is not a non-negative whole number: " + describe(count));
    }
    frames_line_ = frames.line;

    const Token frame = cursor_.next();
    const Token time = frame.text == "Frame" ? cursor_.next() : frame;
    if (frame.text != "Frame" || time.text != "Time:") {
      fail(time.line, "missing 'Frame Time:' after 'Frames:', found " + describe(time));
    }
    const Token seconds = cursor_.next();
    if (!parse_number(seconds.text, clip_.frame_time)) {
      fail(seconds.line, "'Frame Time:' is not a number: " + describe(seconds));
    }
    if (!(std::isfinite(clip_.frame_time) && clip_.frame_time > 0.0f)) {
      fail(seconds.line,
           "'Frame Time:' must be a positive number of seconds, found " + describe(seconds));
    }
    std::string_view rest;
    int line = 0;
    if (cursor_.next_line(rest, line) && !is_blank(rest)) {
      fail(line, "unexpected text after the 'Frame Time:' value: " + in_quotes(rest));
    }
  }

  // "Xrotation of joint 'Hips'": what value c of a row belongs to, for messages.
  std::string channel_label(int c) const {
    for (const motion::ClipJoint& joint : clip_.joints) {
      const int local = c - joint.channel_offset;
      if (local >= 0 && local < static_cast<int>(joint.channels.size())) {
        return std::string(motion::channel_name(joint.channels[local])) + " of joint " +
               in_quotes(joint.name);
      }
    }
    return "no channel";
  }

  void parse_rows() {
    const int channel_count = clip_.channel_count;
    // Position channels are scaled like the offsets; rotations stay in degrees.
    std::vector<float> value_scale(channel_count, 1.0f);
    for (const motion::ClipJoint& joint : clip_.joints) {
      for (std::size_t c = 0; c < joint.channels.size(); ++c) {
        if (!motion::is_rotation(joint.channels[c])) value_scale[joint.channel_offset + c] = scale_;
      }
    }
    // Trust the header's count only as far as the remaining text could hold (>= 2 bytes a value).
    const std::size_t row_bytes = 2 * static_cast<std::size_t>(std::max(channel_count, 1));
    const std::size_t rows = std::min(static_cast<std::size_t>(clip_.header_frame_count),
                                      cursor_.remaining() / row_bytes + 1);
    clip_.values.reserve(rows * channel_count);

    std::string_view line;
    int line_number = 0;
    int frame = 0;
    while (cursor_.next_line(line, line_number)) {
      if (is_blank(line)) continue;
      const std::size_t row_start = clip_.values.size();
      clip_.values.resize(row_start + channel_count);
      float* row = clip_.values.data() + row_start;
      int count = 0;
      for (std::size_t i = 0;;) {
        while (i < line.size() && is_space(line[i])) ++i;
        if (i == line.size()) break;
        const std::size_t start = i;
        while (i < line.size() && !is_space(line[i])) ++i;
        if (count < channel_count) {
          const std::string_view text = line.substr(start, i - start);
          float value = 0.0f;
          if (!parse_number(text, value)) {
            fail(line_number, value_problem(frame, count, text, "is not a number"));
          }
          if (!std::isfinite(value)) {
            fail(line_number, value_problem(frame, count, text, "is NaN or infinite"));
          }
          row[count] = value * value_scale[count];
        }
        ++count;
      }
      if (count != channel_count) {
        fail(line_number, "frame " + std::to_string(frame) + " (counting from 0) has " +
                              std::to_string(count) + " values, expected " +
                              std::to_string(channel_count) + " (one per channel)");
      }
      ++frame;
    }
    clip_.frame_count = frame;
    // Without channels every row is blank: the header is the only frame count there is.
    if (channel_count == 0) clip_.frame_count = clip_.header_frame_count;
    if (clip_.frame_count != clip_.header_frame_count) {
      clip_.warnings.push_back("line " + std::to_string(frames_line_) +
                               ": 'Frames: " + std::to_string(clip_.header_frame_count) +
                               "' disagrees with the " + std::to_string(clip_.frame_count) +
                               " data rows present; using " + std::to_string(clip_.frame_count));
    }
  }

  std::string value_problem(int frame, int c, std::string_view text, const char* problem) const {
    return "frame " + std::to_string(frame) + " (counting from 0), value " + std::to_string(c + 1) +
           " (" + channel_label(c) + ") " + problem + ": " + in_quotes(text);
  }

  TextCursor cursor_;
  const std::filesystem::path& source_;
  float scale_;
  std::optional<motion::UpAxis> up_;
  motion::Clip clip_;
  std::unordered_map<std::string, int> joint_by_name_;
  int frames_line_ = 0;
};

}  // namespace

motion::Clip parse_bvh(std::string_view text, const std::filesystem::path& source,
                       const BvhOptions& options) {
  constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";
  if (text.starts_with(kUtf8Bom)) text.remove_prefix(kUtf8Bom.size());
  return BvhParser(text, source, options).parse();
}

motion::Clip load_bvh(const std::filesystem::path& file, const BvhOptions& options) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) {
    throw LoadError(file,
                    std::filesystem::exists(file, error) ? "not a regular file" : "no such file");
  }
  std::ifstream in(file, std::ios::binary);
  std::string text(std::filesystem::file_size(file, error), '\0');
  if (!in || error || !in.read(text.data(), static_cast<std::streamsize>(text.size()))) {
    throw LoadError(file, "cannot read the file");
  }
  return parse_bvh(text, file, options);
}

}  // namespace sweepd::io
