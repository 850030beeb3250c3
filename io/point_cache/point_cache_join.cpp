#include "io/point_cache/point_cache_join.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>

#include "io/files/load_error.h"
#include "io/point_cache/point_cache_save.h"

namespace sweepd::io {

namespace {

struct Input {
  std::filesystem::path file;
  PointCacheHeader header;
  double first = 0.0;  // PC2: start frame; MDD: first time
};

std::string frames_text(const Input& input) {
  const PointCacheHeader& h = input.header;
  char text[96];
  if (h.format == PointCacheFormat::kPc2)
    std::snprintf(text, sizeof text, "frames %g-%g", h.start_frame,
                  h.start_frame + (h.frame_count - 1) * h.sampling);
  else
    std::snprintf(text, sizeof text, "times %.6g-%.6g s", h.times.front(), h.times.back());
  return input.file.string() + " (" + text + ")";
}

// MDD: the interval between frames, from the first input with two frames or more.
double mdd_interval(const std::vector<Input>& inputs) {
  for (const Input& input : inputs)
    if (input.header.frame_count >= 2) return input.header.times[1] - input.header.times[0];
  throw std::invalid_argument(
      "MDD caches of one frame each carry no frame interval, so their order and gaps cannot be "
      "checked: join PC2 caches (their headers number the frames)");
}

// Throws when `next` does not start right after `previous`.
void check_contiguous(const Input& previous, const Input& next, double interval) {
  const PointCacheHeader& p = previous.header;
  bool follows = false;
  if (p.format == PointCacheFormat::kPc2)
    follows = next.first == previous.first + p.frame_count * double{p.sampling};
  else
    follows = std::abs(next.first - (p.times.back() + interval)) <= 1e-3 * std::abs(interval);
  if (follows) return;
  const bool overlap = p.format == PointCacheFormat::kPc2
                           ? next.first < previous.first + p.frame_count * double{p.sampling}
                           : next.first < p.times.back() + interval;
  throw std::invalid_argument(std::string(overlap ? "overlapping" : "non-contiguous") +
                              " caches: " + frames_text(previous) + " then " + frames_text(next));
}

}  // namespace

JoinedPointCache join_point_caches(const std::vector<std::filesystem::path>& files,
                                   const std::filesystem::path& output) {
  const std::optional<PointCacheFormat> format = point_cache_format(output);
  if (!format)
    throw std::invalid_argument("the joined cache " + output.string() +
                                ": the name must end in .pc2 or .mdd");
  if (files.empty()) throw std::invalid_argument("no caches to join");
  std::vector<Input> inputs;
  for (const std::filesystem::path& file : files) {
    std::error_code ignored;
    if (std::filesystem::equivalent(file, output, ignored))
      throw std::invalid_argument("the joined cache " + output.string() + " is also an input");
    Input input{file, read_point_cache_header(file)};
    if (input.header.format != *format)
      throw std::invalid_argument(
          file.string() + " is " + (input.header.format == PointCacheFormat::kPc2 ? "PC2" : "MDD") +
          ", the joined cache " + output.string() + " not: join caches of its format");
    input.first = input.header.format == PointCacheFormat::kPc2 ? input.header.start_frame
                                                                : input.header.times.front();
    inputs.push_back(std::move(input));
  }
  std::stable_sort(inputs.begin(), inputs.end(),
                   [](const Input& a, const Input& b) { return a.first < b.first; });
  const Input& head = inputs.front();
  const double interval =
      *format == PointCacheFormat::kMdd && inputs.size() > 1 ? mdd_interval(inputs) : 0.0;
  PointCacheHeader joined = head.header;
  joined.frame_count = 0;
  joined.times.clear();
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const PointCacheHeader& h = inputs[i].header;
    if (h.point_count != head.header.point_count)
      throw std::invalid_argument("point counts differ: " + head.file.string() + " has " +
                                  std::to_string(head.header.point_count) + ", " +
                                  inputs[i].file.string() + " " + std::to_string(h.point_count));
    if (h.format == PointCacheFormat::kPc2 && h.sampling != head.header.sampling)
      throw std::invalid_argument("samplings differ: " + head.file.string() + " " +
                                  std::to_string(head.header.sampling) + ", " +
                                  inputs[i].file.string() + " " + std::to_string(h.sampling));
    if (i > 0) check_contiguous(inputs[i - 1], inputs[i], interval);
    if (h.frame_count > INT32_MAX - joined.frame_count)
      throw std::invalid_argument("the joined cache would hold more frames than its 32-bit count");
    joined.frame_count += h.frame_count;
    joined.times.insert(joined.times.end(), h.times.begin(), h.times.end());
  }

  PointCacheWriter writer(output, joined, PointCacheAxes::kGltf);  // the frames' bytes as they are
  std::vector<std::uint8_t> frame(joined.frame_size());
  int index = 0;
  for (const Input& input : inputs) {
    std::ifstream in(input.file, std::ios::binary);
    in.seekg(static_cast<std::streamoff>(input.header.header_size()));
    for (int f = 0; f < input.header.frame_count; ++f) {
      if (!in.read(reinterpret_cast<char*>(frame.data()), std::streamsize(frame.size())))
        throw LoadError(input.file, "cannot read frame " + std::to_string(f));
      writer.write_frame_bytes(index++, frame);
    }
  }
  writer.finish();
  return {joined, static_cast<int>(inputs.size())};
}

}  // namespace sweepd::io
