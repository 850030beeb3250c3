// render_frames: a render-farm client — one OpenEXR position map per frame of a BVH clip,
// rendered by sweepd.
//
//   render_frames --server HOST:PORT [--token T] [--model NAME | --model-file F.glb]
//                 --bvh CLIP [--bvh-scale S] --frames A-B -o DIR [--width W --height H]
//                 [--compression zip|none|zips|piz] [--normals] [--method sweep|lbs|dqs]
//
// 1. Read the clip and check the range A-B (inclusive, 0-based) against its frames.
// 2. Resume: a frame whose file DIR/<clip stem>.<frame, 5 digits>.exr exists and opens as a
//    complete OpenEXR file is skipped; a truncated or corrupt one is rendered again (said on
//    stderr). With every frame complete the server is not contacted.
// 3. Connect, Hello, choose the model (--model NAME, default "mannequin", or upload
//    --model-file), retarget the clip onto the skeleton ModelInfo carries.
// 4. Each remaining frame → one PositionMapRequest (positions and coverage, normals with
//    --normals), up to Welcome.max_poses_in_flight in flight. The reply's EXR bytes are written
//    to DIR/.<name>.partial and renamed, so a file present under its name is complete.
// 5. A progress bar on stderr (console/progress_bar.h: frames done/total, rate, ETA); at the
//    end, on stdout:
//    "rendered R, skipped S of T frames in X s".
//
// Exit codes: 0 every frame present (or --help); 1 the server or a file refused (unreachable
// server, unknown model, a frame's Error, a write failure), named on stderr; 2 a usage error
// (flags, "12x" where a number is expected, the range), naming the flag.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "client/client_tls_flags.h"
#include "client/connection.h"
#include "client/model_skeleton.h"
#include "console/command_line.h"
#include "console/progress_bar.h"
#include "io/bvh_load.h"
#include "motion/frame_range.h"
#include "protocol/messages.h"

namespace {

namespace fs = std::filesystem;
namespace pb = sweepd::protocol;
using Clock = std::chrono::steady_clock;

// Problems with the command line (exit code 2); anything else thrown is exit code 1.
struct UsageError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

struct Options {
  std::string server, token, model = "mannequin", model_file, bvh, frames;
  fs::path out_dir;
  float bvh_scale = 0.056444f;  // CMU inches to metres
  std::uint32_t width = 1024, height = 1024;
  pb::ExrCompression compression = pb::ExrCompression::Zip;
  pb::DeformMethod method = pb::DeformMethod::Sweep;
  bool normals = false;
  sweepd::client::ClientTls tls;
};

// The command line (console/command_line.h: --help exits 0, a bad flag or value exits 2).
void describe(CLI::App& app, Options& o) {
  app.description("One OpenEXR position map per frame of a BVH clip, rendered by sweepd.");
  app.add_option("--server", o.server, "sweepd's HOST:PORT")->required();
  app.add_option("--token", o.token, "the daemon's auth token");
  sweepd::client::add_client_tls_flags(app, o.tls);
  app.add_option("--model", o.model, "a model the server has, by name")->capture_default_str();
  app.add_option("--model-file", o.model_file, "a .glb to upload instead of --model");
  app.add_option("--bvh", o.bvh, "the clip")->required();
  app.add_option("--bvh-scale", o.bvh_scale, "metres per clip unit (CMU: 0.056444)")
      ->capture_default_str();
  app.add_option("--frames", o.frames, "A-B: the clip frames, inclusive, 0-based")->required();
  app.add_option("-o", o.out_dir, "DIR: where the .exr files go")->required();
  app.add_option("--width", o.width, "map width in texels")
      ->check(sweepd::console::whole_number(1, 4096))
      ->capture_default_str();
  app.add_option("--height", o.height, "map height in texels")
      ->check(sweepd::console::whole_number(1, 4096))
      ->capture_default_str();
  const std::map<std::string, pb::ExrCompression> compressions = {
      {"zip", pb::ExrCompression::Zip},
      {"none", pb::ExrCompression::Uncompressed},
      {"zips", pb::ExrCompression::Zips},
      {"piz", pb::ExrCompression::Piz}};
  sweepd::console::add_choice(app, "--compression", o.compression, compressions,
                              "zip (default), none, zips or piz");
  app.add_flag("--normals", o.normals, "also the N layer");
  const std::map<std::string, pb::DeformMethod> methods = {{"sweep", pb::DeformMethod::Sweep},
                                                           {"lbs", pb::DeformMethod::Lbs},
                                                           {"dqs", pb::DeformMethod::Dqs}};
  sweepd::console::add_choice(app, "--method", o.method, methods, "sweep (default), lbs or dqs");
}

// A model file to upload, whole.
std::vector<std::uint8_t> file_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + file.string());
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// "A-B" (or "A"); a usage error for anything else.
sweepd::motion::FrameRange parse_range(const std::string& text) {
  const std::optional<sweepd::motion::FrameRange> range = sweepd::motion::parse_frame_range(text);
  if (!range) throw UsageError("--frames " + text + ": expected A-B, e.g. 0-239");
  return *range;
}

// The range within a clip of `frame_count` frames.
sweepd::motion::FrameRange clip_range(const std::string& text, int frame_count) {
  const sweepd::motion::FrameRange range = parse_range(text);
  if (const std::string problem = sweepd::motion::frame_range_problem(range, frame_count);
      !problem.empty())
    throw UsageError("--frames " + text + ": " + problem);
  return range;
}

fs::path frame_file(const Options& options, int frame) {
  char number[16];
  std::snprintf(number, sizeof number, "%05d", frame);
  return options.out_dir / (fs::path(options.bvh).stem().string() + "." + number + ".exr");
}

// Why `file` is not a complete OpenEXR file, or "" when it is. isComplete() only checks that
// every chunk has an offset, so the first channel is also decoded (into one reused row), which
// finds truncated and corrupt chunks.
std::string incomplete_reason(const fs::path& file) {
  try {
    Imf::InputFile exr(file.c_str());
    if (!exr.isComplete()) return "chunks missing";
    const Imath::Box2i window = exr.header().dataWindow();
    const Imf::Channel& channel = exr.header().channels().begin().channel();
    std::vector<float> row(static_cast<std::size_t>(window.max.x - window.min.x + 1));
    Imf::FrameBuffer frame_buffer;
    frame_buffer.insert(exr.header().channels().begin().name(),
                        Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(row.data() - window.min.x),
                                   sizeof(float), 0, channel.xSampling, channel.ySampling));
    exr.setFrameBuffer(frame_buffer);
    exr.readPixels(window.min.y, window.max.y);
    return "";
  } catch (const std::exception& error) {
    return error.what();
  }
}

void write_file(const fs::path& file, const pb::PositionMap& map) {
  const fs::path partial = file.parent_path() / ("." + file.filename().string() + ".partial");
  {
    std::ofstream out(partial, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(map.exr()->data()),
              static_cast<std::streamsize>(map.exr()->size()));
    if (!out.flush()) throw std::runtime_error("cannot write " + partial.string());
  }
  fs::rename(partial, file);
}

int run(const Options& options) {
  const sweepd::motion::Clip motion =
      sweepd::io::load_bvh(options.bvh, {.length_scale = options.bvh_scale});
  const sweepd::motion::FrameRange range = clip_range(options.frames, motion.frame_count);
  fs::create_directories(options.out_dir);

  // Resume: only frames without a complete file are rendered.
  std::deque<int> todo;
  for (int frame = range.first; frame <= range.last; ++frame) {
    const fs::path file = frame_file(options, frame);
    if (!fs::exists(file)) {
      todo.push_back(frame);
    } else if (const std::string reason = incomplete_reason(file); !reason.empty()) {
      std::fprintf(stderr, "%s is not a complete EXR (%s): rendering it again\n", file.c_str(),
                   reason.c_str());
      todo.push_back(frame);
    }
  }
  const int total = range.count();
  const int skipped = total - static_cast<int>(todo.size());
  const Clock::time_point start = Clock::now();
  auto report = [&](int rendered) {
    std::printf("rendered %d, skipped %d of %d frames in %.2f s\n", rendered, skipped, total,
                std::chrono::duration<double>(Clock::now() - start).count());
  };
  if (todo.empty()) {  // nothing to ask the server for
    report(0);
    return 0;
  }

  sweepd::client::Connection channel(options.server, options.tls);
  const std::uint32_t window =
      std::max(1u, channel.hello(options.token, "render_frames").max_poses_in_flight());
  const pb::ModelInfo& info =
      options.model_file.empty()
          ? channel.load_model(options.model)
          : channel.load_model(options.model_file, file_bytes(options.model_file));
  const std::uint32_t model_id = info.model_id();
  const std::size_t joint_count = info.joint_names()->size();
  const sweepd::motion::Retargeter clip = sweepd::client::retarget_onto(info, motion);

  auto send_frame = [&](int frame) {
    const sweepd::deform::Pose pose = clip.pose_at_frame(frame);
    std::vector<pb::Quat> rotations(joint_count);
    for (std::size_t j = 0; j < joint_count; ++j) {
      const glm::quat& q = pose.local_rotations[j];
      rotations[j] = pb::Quat(q.x, q.y, q.z, q.w);
    }
    pb::PoseFields fields;
    fields.model_id = model_id;
    fields.sequence = static_cast<std::uint64_t>(frame) + 1;  // sequences start at 1
    fields.rotations = rotations;
    fields.root_translation =
        pb::Vec3(pose.root_translation.x, pose.root_translation.y, pose.root_translation.z);
    fields.method = options.method;
    flatbuffers::FlatBufferBuilder& builder = channel.builder();
    builder.Clear();
    auto layers = pb::MapLayers::Position | pb::MapLayers::Coverage;
    if (options.normals) layers = layers | pb::MapLayers::Normal;
    const auto request =
        pb::CreatePositionMapRequest(builder, pb::add_pose(builder, fields), options.width,
                                     options.height, options.compression, layers);
    channel.send(pb::finish_message(builder, request));
  };

  // Pipelined: up to `window` requests in flight, answered in order; each reply is written as
  // it arrives.
  std::deque<int> in_flight;
  int rendered = 0;
  {  // the bar finishes its line before the report
    sweepd::console::ProgressBar bar("rendering " + fs::path(options.bvh).stem().string());
    auto show_progress = [&]() {  // the rate counts this run's renders, not the skipped frames
      const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
      char detail[64];
      std::snprintf(detail, sizeof detail, "%d/%d, %.1f frames/s", skipped + rendered, total,
                    seconds > 0.0 ? rendered / seconds : 0.0);
      bar.update(static_cast<double>(skipped + rendered) / total, "frames", detail);
    };
    show_progress();
    while (!todo.empty() || !in_flight.empty()) {
      while (!todo.empty() && in_flight.size() < window) {
        send_frame(todo.front());
        in_flight.push_back(todo.front());
        todo.pop_front();
      }
      const int frame = in_flight.front();
      in_flight.pop_front();
      try {
        const pb::PositionMap& map = channel.expect<pb::PositionMap>();
        if (map.sequence() != static_cast<std::uint64_t>(frame) + 1) {
          throw std::runtime_error("the answer is for pose " + std::to_string(map.sequence()));
        }
        write_file(frame_file(options, frame), map);
      } catch (const std::exception& error) {
        throw std::runtime_error("frame " + std::to_string(frame) + ": " + error.what());
      }
      ++rendered;
      show_progress();
    }
  }
  channel.close("frames rendered");
  report(rendered);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app("", "render_frames");
  describe(app, options);
  if (const std::optional<int> exit_code = sweepd::console::parse_command_line(app, argc, argv))
    return *exit_code;
  try {
    parse_range(options.frames);  // the syntax, before the clip is read
    return run(options);
  } catch (const UsageError& error) {
    std::fprintf(stderr, "render_frames: %s\n", error.what());
    return 2;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "\nrender_frames: %s\n", error.what());
    return 1;
  }
}
