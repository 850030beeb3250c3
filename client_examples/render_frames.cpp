// render_frames: a render-farm client — one OpenEXR position map per frame of a clip (BVH, or
// a glTF file's animation), or one PC2 or MDD point cache of the range, rendered by one or more
// sweepd servers.
//
//   render_frames --server HOST:PORT[,HOST:PORT...] [--token T | --token-file FILE]
//                 [--model NAME] [--model-file F.glb]
//                 (--bvh CLIP [--bvh-scale S] | --clip-from F.glb [--clip NAME|INDEX] |
//                  --range-of-motion)
//                 --frames A-B [--shard I/N] -o DIR [--width W --height H]
//                 [--compression zip|none|zips|piz] [--normals] [--half-normals]
//                 [--method sweep|lbs|dqs] [--format exr|pc2|mdd [--axes gltf|blender]]
//                 [--timeout SECONDS] [--attempts N]
//
// 1. Read the clip and check the range A-B (inclusive, 0-based) against its frames (with
//    --range-of-motion, protocol 1.13, there is no file: the server builds the model's range of
//    motion, 1,441 frames for a full rig, and refuses each frame past its end). With
//    --shard I/N (or, without it, JOB_COMPLETION_INDEX and JOB_COMPLETIONS from a Kubernetes
//    Indexed Job) only the I-th of N contiguous slices of the range is this process's
//    (client/frame_shard.h).
// 2. Resume: a frame whose file DIR/<clip stem>.<frame, 5 digits>.exr exists and opens as a
//    complete OpenEXR file is skipped; a truncated or corrupt one is removed and rendered again
//    (said on stderr). With every frame complete no server is contacted.
// 3. One thread per server (a list, or one address behind HAProxy): connect, Hello, choose the
//    model (--model NAME, default "mannequin", or upload --model-file under --model NAME, else
//    under the file's base name: "body" for dir/body.glb; the name the server holds is said
//    on stderr once), upload the clip once
//    with UploadClip (client_examples/clip_file_flags.h: a BVH's text, or a glTF file's bytes and
//    the animation's name, protocol 1.7) so that the server retargets it (each frame is asked for
//    by clip id and frame number, not as a pose), then take frames from one shared queue
//    (client/frame_queue.h), up to the server's Welcome.max_poses_in_flight in flight. The
//    model goes by its content id after the first server's answer (client/model_source.h):
//    a replica sharing the store finds it there; one that answers UnknownModel (or
//    UnknownClip) — at load or for a frame — gets the upload again (the count is on stderr when
//    above one).
// 4. Failures: a server that dies, closes, or sends nothing for --timeout seconds (default 60;
//    the TLS handshake included)
//    loses its frames in flight back to the queue, where the next server to ask takes them
//    (elsewhere, when there is an elsewhere); its thread connects again after 0.2, 0.4, 0.8,
//    1.6 s and gives up after 5 failed tries in a row. A frame is tried at most --attempts
//    times (default 3). A server that refuses the job (token, model, no position maps) is not
//    used again. A frame the server finds invalid fails at once.
// 5. Each reply's EXR bytes are written to DIR/.<name>.<pid>.partial and renamed without
//    replacing (renameat2 RENAME_NOREPLACE): a file under its name is complete and written
//    once, even with two processes on one range.
//    With --format pc2|mdd (point caches, io/point_cache/point_cache_save.h) each frame is asked for as
//    posed vertices (PoseFromClip, no normals) and written at its own place in one cache,
//    DIR/<clip stem>.<first frame>-<last frame, 5 digits each>.pc2 (or .mdd) for this process's
//    frames (its shard's slice), in the model's glTF axes, or Blender's Z-up with --axes blender
//    (sweepctl pose's flag and names). The cache is DIR/<name>.partial until its last frame is
//    in, then renamed: a complete cache is skipped on a rerun, a partial one rendered again
//    whole. `sweepctl join-cache` joins the shards' caches into one.
// 6. A progress bar on stderr (console/progress_bar.h); at the end, on stdout:
//    "rendered R, skipped S of T frames in X s (F frames/s), retried Q, failed P"; on stderr
//    the failed frames, a line per cause ("560 frames failed (1441-2000): ..."), and with
//    several servers the frames each one rendered.
//
// Exit codes: 0 every frame present (or --help); 1 a frame failed (unreachable servers, unknown
// model, a frame's Error, a write failure), named on stderr; 2 a usage error (flags, "12x"
// where a number is expected, the range, the shard), naming the flag.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <fcntl.h>  // AT_FDCWD
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>  // renameat2
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "client/bind_warnings.h"
#include "client/client_tls_flags.h"
#include "client/connection.h"
#include "client/frame_queue.h"
#include "client/frame_shard.h"
#include "client/model_source.h"
#include "client/pose_error.h"
#include "client/token_flags.h"
#include "client_examples/clip_file_flags.h"
#include "console/command_line.h"
#include "console/frame_failures.h"
#include "console/frame_range.h"
#include "console/progress_bar.h"
#include "deform/job/method_choice.h"
#include "io/files/file_bytes.h"
#include "io/files/load_error.h"
#include "io/point_cache/point_cache_save.h"
#include "protocol/messages.h"

namespace {

namespace fs = std::filesystem;
namespace pb = sweepd::protocol;
using Clock = std::chrono::steady_clock;

constexpr sweepd::deform::MethodNames kPoseMethods = sweepd::deform::MethodNames::kPlainMethods;

pb::DeformMethod wire_method(sweepd::deform::DeformMethod method) {
  switch (method) {
    case sweepd::deform::DeformMethod::kLbs:
      return pb::DeformMethod::Lbs;
    case sweepd::deform::DeformMethod::kDqs:
      return pb::DeformMethod::Dqs;
    case sweepd::deform::DeformMethod::kSweep:
      break;
  }
  return pb::DeformMethod::Sweep;
}

enum class OutputFormat { kExr, kPc2, kMdd };

// Problems with the command line (exit code 2); anything else thrown is exit code 1.
struct UsageError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

struct Options {
  std::string server, token, model, model_file, frames, shard;
  fs::path out_dir;
  sweepd::client_examples::ClipFile clip;
  std::uint32_t width = 1024, height = 1024;
  pb::ExrCompression compression = pb::ExrCompression::Zip;
  pb::DeformMethod method = pb::DeformMethod::Sweep;
  bool normals = false, half_normals = false;
  OutputFormat format = OutputFormat::kExr;
  sweepd::io::PointCacheAxes axes = sweepd::io::PointCacheAxes::kGltf;
  int timeout_ms = 60000, attempts = 3;
  sweepd::client::ClientTls tls;
  bool point_cache() const { return format != OutputFormat::kExr; }
};

// The command line (console/command_line.h: --help exits 0, a bad flag or value exits 2).
void describe(CLI::App& app, Options& o) {
  app.description(
      "One OpenEXR position map per frame of a clip, or a PC2 or MDD point cache of the "
      "frames, rendered by sweepd.");
  app.add_option("--server", o.server,
                 "sweepd's HOST:PORT, or several, comma-separated: HOST:PORT,HOST:PORT")
      ->required();
  sweepd::client::add_token_flags(app, o.token);
  sweepd::client::add_client_tls_flags(app, o.tls);
  app.add_option("--model", o.model,
                 "a model the server has, by name (default: mannequin); with --model-file, the "
                 "name to upload it under (default: the file's base name)");
  app.add_option("--model-file", o.model_file, "a .glb to upload");
  sweepd::client_examples::add_clip_file_flags(app, o.clip);
  app.add_option("--frames", o.frames, "A-B: the clip frames, inclusive, 0-based")->required();
  app.add_option("--shard", o.shard,
                 "I/N: render only the I-th (0-based) of N slices of the range (default: "
                 "JOB_COMPLETION_INDEX/JOB_COMPLETIONS when set)");
  app.add_option("-o", o.out_dir, "DIR: where the .exr files (or the point cache) go")->required();
  sweepd::console::add_choice(
      app, "--format", o.format,
      std::map<std::string, OutputFormat>{
          {"exr", OutputFormat::kExr}, {"pc2", OutputFormat::kPc2}, {"mdd", OutputFormat::kMdd}},
      "exr (default: a position map per frame), or one point cache of the frames: pc2 or mdd");
  sweepd::console::add_choice(app, "--axes", o.axes, sweepd::io::point_cache_axes_names(),
                              sweepd::io::kPointCacheAxesHelp)
      ->type_name("gltf|blender");
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
  app.add_flag("--half-normals", o.half_normals, "the N layer as float16 (implies --normals)");
  // The names as sweepctl and the daemon take them (the one parser), sent as the wire's enum.
  app.add_option("--method", "sweep (default), lbs or dqs")
      ->check(CLI::Validator(
          [](std::string& name) { return sweepd::deform::method_name_problem(name, kPoseMethods); },
          ""))
      ->each([&o](const std::string& name) {
        o.method = wire_method(sweepd::deform::parse_method_choice(name, kPoseMethods).method);
      });
  app.add_option_function<int>(
         "--timeout", [&o](int seconds) { o.timeout_ms = seconds * 1000; },
         "SECONDS a server may take to answer before its frames go elsewhere (default 60)")
      ->check(sweepd::console::whole_number(1, 86400));
  app.add_option("--attempts", o.attempts, "tries per frame before it fails")
      ->check(sweepd::console::whole_number(1, 100))
      ->capture_default_str();
}

// The flags that apply to one output only: --axes to a point cache, the map's to EXR files.
void check_format_flags(const CLI::App& app, const Options& options) {
  if (!options.point_cache()) {
    if (app.count("--axes") > 0)
      throw UsageError("--axes applies to a point cache: --format pc2 or mdd");
    return;
  }
  for (const char* flag : {"--width", "--height", "--compression", "--normals", "--half-normals"})
    if (app.count(flag) > 0)
      throw UsageError(std::string(flag) +
                       " applies to EXR position maps, not to a point cache (--format " +
                       (options.format == OutputFormat::kPc2 ? "pc2" : "mdd") + ")");
}

// "A-B" (or "A"); a usage error for anything else.
sweepd::console::FrameRange parse_range(const std::string& text) {
  const std::optional<sweepd::console::FrameRange> range = sweepd::console::parse_frame_range(text);
  if (!range) throw UsageError("--frames " + text + ": expected A-B, e.g. 0-239");
  return *range;
}

// The range within a clip of `frame_count` frames (unknown: the server checks each frame).
sweepd::console::FrameRange clip_range(const std::string& text, std::optional<int> frame_count) {
  const sweepd::console::FrameRange range = parse_range(text);
  if (!frame_count) return range;
  if (const std::string problem = sweepd::console::frame_range_problem(range, *frame_count);
      !problem.empty())
    throw UsageError("--frames " + text + ": " + problem);
  return range;
}

fs::path frame_file(const Options& options, int frame) {
  char number[16];
  std::snprintf(number, sizeof number, "%05d", frame);
  return options.out_dir / (fs::path(options.clip.file()).stem().string() + "." + number + ".exr");
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

// The point cache of this process's frames: DIR/<clip stem>.AAAAA-BBBBB.pc2 (or .mdd).
fs::path cache_file(const Options& options, const sweepd::console::FrameRange& frames) {
  char range[32];
  std::snprintf(range, sizeof range, "%05d-%05d", frames.first, frames.last);
  return options.out_dir / (fs::path(options.clip.file()).stem().string() + "." + range +
                            (options.format == OutputFormat::kPc2 ? ".pc2" : ".mdd"));
}

// Why `file` is not this run's complete cache of `frames`, or "" when it is.
std::string incomplete_cache_reason(const fs::path& file,
                                    const sweepd::console::FrameRange& frames) {
  try {
    const sweepd::io::PointCacheHeader header = sweepd::io::read_point_cache_header(file);
    if (header.frame_count != frames.count())
      return std::to_string(header.frame_count) + " frames, not " + std::to_string(frames.count());
    if (header.format == sweepd::io::PointCacheFormat::kPc2 &&
        header.start_frame != static_cast<float>(frames.first))
      return "its start frame is " + std::to_string(header.start_frame);
    return "";
  } catch (const sweepd::io::LoadError& error) {
    return error.reason();
  }
}

// The one point cache the server threads write their frames into, each at its place: created
// at the first frame (the model's vertex count and the clip's frame rate come from the
// server), finished when every frame is in.
class CacheSink {
 public:
  CacheSink(fs::path file, const Options& options, const sweepd::console::FrameRange& frames)
      : file_(std::move(file)), options_(options), frames_(frames) {}

  void write(int frame, const pb::PosedVertices& reply, float clip_frames_per_second) {
    std::vector<glm::vec3> positions(reply.vertex_count());
    if (!pb::copy_positions(reply,
                            {reinterpret_cast<float*>(positions.data()), positions.size() * 3}))
      throw std::runtime_error("frame " + std::to_string(frame) +
                               ": the reply's positions do not match its vertex count");
    const std::lock_guard lock(mutex_);
    if (!writer_) {
      writer_.emplace(
          file_,
          sweepd::io::PointCacheLayout{
              .format = options_.format == OutputFormat::kPc2 ? sweepd::io::PointCacheFormat::kPc2
                                                              : sweepd::io::PointCacheFormat::kMdd,
              .axes = options_.axes,
              .point_count = static_cast<int>(positions.size()),
              .frame_count = frames_.count(),
              .first_frame = frames_.first,
              .frames_per_second = clip_frames_per_second > 0.0f ? clip_frames_per_second : 30.0});
      point_count_ = static_cast<int>(positions.size());
    }
    if (static_cast<int>(positions.size()) != point_count_)
      throw std::runtime_error("frame " + std::to_string(frame) + " has " +
                               std::to_string(positions.size()) + " vertices, the cache " +
                               std::to_string(point_count_) +
                               ": the servers do not hold one model");
    writer_->write_frame_at(frame - frames_.first, positions);
  }
  // Renames the complete cache into place; the vertex count.
  int finish() {
    writer_->finish();
    return point_count_;
  }
  const fs::path& file() const { return file_; }

 private:
  std::mutex mutex_;
  fs::path file_;
  const Options& options_;
  sweepd::console::FrameRange frames_;
  std::optional<sweepd::io::PointCacheWriter> writer_;
  int point_count_ = 0;
};

// The progress bar, shared by the server threads.
class Progress {
 public:
  Progress(const std::string& title, int skipped, int total)
      : bar_(title), skipped_(skipped), total_(total) {
    show();
  }
  void frame_rendered() {
    const std::lock_guard lock(mutex_);
    ++rendered_;
    show();
  }

 private:
  void show() {  // the rate counts this run's renders, not the skipped frames
    const double seconds = std::chrono::duration<double>(Clock::now() - start_).count();
    char detail[64];
    std::snprintf(detail, sizeof detail, "%d/%d, %.1f frames/s", skipped_ + rendered_, total_,
                  seconds > 0.0 ? rendered_ / seconds : 0.0);
    bar_.update(static_cast<double>(skipped_ + rendered_) / total_, "frames", detail);
  }
  std::mutex mutex_;
  sweepd::console::ProgressBar bar_;
  const Clock::time_point start_ = Clock::now();
  int skipped_, total_, rendered_ = 0;
};

// What every server thread reads.
struct Job {
  const Options& options;
  sweepd::client::ModelSource& model;  // uploaded only to servers that lack it
  sweepd::client::FrameQueue& queue;
  Progress& progress;
  std::once_flag& reported;  // the model's name and the clip's warnings said once
  CacheSink* cache;          // the point cache (--format pc2|mdd), else null: EXR files
};

// What an Error reply means for the frame and the server.
enum class ErrorMeaning {
  kFrameInvalid,  // the frame would get it anywhere: it fails
  kServerBusy,    // at a limit for now: the frame goes back to the queue
  kServerUnfit,   // this server cannot do this job (token, model, no maps): not used again
  kModelLost,     // the server does not hold the model (a replica without the shared store):
                  // connect again, which loads it there again
};

ErrorMeaning meaning_of(pb::ErrorCode code) {
  switch (code) {
    case pb::ErrorCode::InvalidPose:
    case pb::ErrorCode::WrongJointCount:
    case pb::ErrorCode::InvalidArgument:
      return ErrorMeaning::kFrameInvalid;
    case pb::ErrorCode::Internal:
    case pb::ErrorCode::MemoryLimit:
    case pb::ErrorCode::ResourceExhausted:
    case pb::ErrorCode::ConnectionLimit:
    case pb::ErrorCode::ShuttingDown:
      return ErrorMeaning::kServerBusy;
    case pb::ErrorCode::UnknownModel:
    case pb::ErrorCode::UnknownClip:
      return ErrorMeaning::kModelLost;
    default:
      return ErrorMeaning::kServerUnfit;
  }
}

// A server that cannot do this job; its thread stops.
struct ServerUnfit : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Writes a reply's EXR bytes under a name no other process uses, then renames it into place
// without replacing: false when another process wrote the frame first (its file is kept).
bool write_file(const fs::path& file, const pb::PositionMap& map) {
  const fs::path partial = file.parent_path() / ("." + file.filename().string() + "." +
                                                 std::to_string(getpid()) + ".partial");
  {
    std::ofstream out(partial, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(map.exr()->data()),
              static_cast<std::streamsize>(map.exr()->size()));
    if (!out.flush()) throw std::runtime_error("cannot write " + partial.string());
  }
  if (renameat2(AT_FDCWD, partial.c_str(), AT_FDCWD, file.c_str(), RENAME_NOREPLACE) == 0)
    return true;
  const int error = errno;
  fs::remove(partial);
  if (error == EEXIST) return false;
  throw std::runtime_error("cannot rename " + partial.string() + ": " + std::strerror(error));
}

// The TLS settings with --timeout bounding the handshake too: a server that accepts and never
// answers is left like one that stops answering frames.
sweepd::client::ClientTls with_handshake_timeout(const Options& options) {
  sweepd::client::ClientTls tls = options.tls;
  tls.handshake_timeout = std::chrono::milliseconds(options.timeout_ms);
  return tls;
}

// One connection to one server: set up for the job, then frames until the queue has ended.
// Frames it holds are in `in_flight`, so that the caller can give them back when it throws.
class ServerSession {
 public:
  ServerSession(const std::string& address, const Job& job)
      : job_(job), channel_(address, with_handshake_timeout(job.options)) {
    channel_.set_receive_timeout(std::chrono::milliseconds(job.options.timeout_ms));
    try {
      window_ =
          std::max(1u, channel_.hello(job.options.token, "render_frames").max_poses_in_flight());
      const pb::ModelInfo& info = job.model.load(channel_);
      model_id_ = info.model_id();
      const std::string model_name = info.name()->str();  // `info` is invalid after a receive
      const std::vector<std::string> bind_warnings = sweepd::client::bind_warning_lines(info);
      const pb::ClipInfo& clip =
          sweepd::client_examples::upload_clip_file(channel_, job.options.clip, model_id_);
      clip_id_ = clip.clip_id()->str();
      clip_frames_per_second_ = clip.frames_per_second();
      // Once per job: the model's name on the server, (protocol 1.14) where the server's
      // self-check found its sweep worse than skinning, the reader's warnings and (protocol
      // 1.12) what playing the clip on the model leaves unmapped.
      std::call_once(job.reported, [&] {
        std::fprintf(stderr, "render_frames: model '%s' (id %u) on %s\n", model_name.c_str(),
                     model_id_, address.c_str());
        for (const std::string& line : bind_warnings)
          std::fprintf(stderr, "warning: %s\n", line.c_str());
        if (clip.warnings())
          for (const flatbuffers::String* warning : *clip.warnings())
            std::fprintf(stderr, "warning: %s: %s\n", job.options.clip.file().c_str(),
                         warning->c_str());
      });
    } catch (const sweepd::client::ServerError& error) {
      if (meaning_of(error.code()) == ErrorMeaning::kServerBusy) throw;
      throw ServerUnfit(error.what());
    }
  }

  // Renders until the queue has ended, counting the frames it writes into `rendered`.
  void render(std::deque<int>& in_flight, int& rendered) {
    sweepd::client::FrameQueue& queue = job_.queue;
    for (;;) {
      while (in_flight.size() < window_) {
        const std::optional<int> frame = queue.take(/*wait=*/in_flight.empty());
        if (!frame) break;
        send_frame(*frame);
        in_flight.push_back(*frame);
      }
      if (in_flight.empty()) {
        channel_.close("frames rendered");
        return;
      }
      const pb::Message& message = channel_.receive();
      if (const pb::Error* error = message.body_as_Error()) {
        // A refused pose's Error comes at once, ahead of the replies to the poses before it
        // (protocol/README.md): its sequence names its frame; one naming none is the oldest's.
        const auto refused =
            std::find(in_flight.begin(), in_flight.end(), static_cast<int>(error->sequence()) - 1);
        const int frame = refused != in_flight.end() ? *refused : in_flight.front();
        const std::string name = "frame " + std::to_string(frame);
        // The queue keeps the cause per frame (summed up per cause at the end), the
        // exceptions name the frame.
        const std::string cause = sweepd::client::pose_error_cause(*error);
        const std::string why = name + ": " + cause;
        const ErrorMeaning meaning = meaning_of(error->code());
        // Unfit for every frame (it renders no maps): the cause, not this frame, fails the rest.
        if (meaning == ErrorMeaning::kServerUnfit) throw ServerUnfit(cause);
        // The server closes, or no longer holds the model: connect again.
        if (error->fatal() || meaning == ErrorMeaning::kModelLost) throw std::runtime_error(why);
        in_flight.erase(refused != in_flight.end() ? refused : in_flight.begin());
        if (meaning == ErrorMeaning::kFrameInvalid) {
          queue.fail(frame, cause);
        } else {
          queue.retry(frame, cause);
          std::this_thread::sleep_for(std::chrono::milliseconds(200));  // let it catch up
        }
        continue;
      }
      const int frame = in_flight.front();  // replies come in the order the poses were sent
      const std::string name = "frame " + std::to_string(frame);
      if (job_.cache) {
        const pb::PosedVertices* posed = message.body_as_PosedVertices();
        if (!posed) throw std::runtime_error(name + ": the reply is not posed vertices");
        check_sequence(name, posed->sequence(), frame);
        job_.cache->write(frame, *posed, clip_frames_per_second_);
      } else {
        const pb::PositionMap* map = message.body_as_PositionMap();
        if (!map || !map->exr())
          throw std::runtime_error(name + ": the reply is not a position map");
        check_sequence(name, map->sequence(), frame);
        const fs::path file = frame_file(job_.options, frame);
        if (!write_file(file, *map)) {
          std::fprintf(stderr, "\n%s: another process wrote it first; kept that file\n",
                       file.c_str());
        }
      }
      in_flight.pop_front();
      queue.rendered(frame);
      job_.progress.frame_rendered();
      ++rendered;
    }
  }

 private:
  static void check_sequence(const std::string& name, std::uint64_t sequence, int frame) {
    if (sequence != static_cast<std::uint64_t>(frame) + 1)
      throw std::runtime_error(name + ": the answer is for pose " + std::to_string(sequence));
  }

  // A PositionMapRequest for `frame` (a PoseFromClip for a point cache: its positions, without
  // normals): the held clip's frame number (the pose names only the model and method).
  void send_frame(int frame) {
    pb::PoseFields fields;
    fields.model_id = model_id_;
    fields.sequence = static_cast<std::uint64_t>(frame) + 1;  // sequences start at 1
    fields.method = job_.options.method;
    flatbuffers::FlatBufferBuilder& builder = channel_.builder();
    builder.Clear();
    if (job_.cache) {
      const auto pose = pb::add_pose(builder, fields);
      const auto clip = pb::CreateClipFrame(builder, builder.CreateString(clip_id_),
                                            static_cast<std::uint32_t>(frame));
      channel_.send(pb::finish_message(builder, pb::CreatePoseFromClip(builder, pose, clip)));
      return;
    }
    auto layers = pb::MapLayers::Position | pb::MapLayers::Coverage;
    if (job_.options.normals || job_.options.half_normals) layers = layers | pb::MapLayers::Normal;
    const auto pose = pb::add_pose(builder, fields);
    const auto clip = pb::CreateClipFrame(builder, builder.CreateString(clip_id_),
                                          static_cast<std::uint32_t>(frame));
    const auto request = pb::CreatePositionMapRequest(builder, pose, job_.options.width,
                                                      job_.options.height, job_.options.compression,
                                                      layers, job_.options.half_normals, clip);
    channel_.send(pb::finish_message(builder, request));
  }

  const Job& job_;
  sweepd::client::Connection channel_;
  std::uint32_t window_ = 1, model_id_ = 0;
  std::string clip_id_;                  // the server's id for the clip
  float clip_frames_per_second_ = 0.0f;  // its own rate: an MDD cache's frame times
};

// One server's thread: sessions until the queue has ended, connecting again after a failure
// and giving up after kTries failures in a row or when the server is unfit. Returns the frames
// it rendered.
int serve(const std::string& address, const Job& job) {
  constexpr int kTries = 5;
  int rendered = 0, failures = 0;
  std::chrono::milliseconds pause(200);
  for (;;) {
    std::deque<int> in_flight;
    auto give_back = [&](const std::string& why) {  // in reverse, so they go out in order again
      for (auto frame = in_flight.rbegin(); frame != in_flight.rend(); ++frame)
        job.queue.retry(*frame, why);
    };
    try {
      ServerSession session(address, job);
      failures = 0;
      pause = std::chrono::milliseconds(200);
      session.render(in_flight, rendered);
      job.queue.retire("");  // the queue has ended: nothing is waiting
      return rendered;
    } catch (const ServerUnfit& error) {
      const std::string why = address + ": " + error.what();
      std::fprintf(stderr, "\nrender_frames: %s; not using it again\n", why.c_str());
      give_back(why);
      job.queue.retire(why);
      return rendered;
    } catch (const std::exception& error) {
      const std::string why = address + ": " + error.what();
      give_back(why);
      if (++failures == kTries) {
        std::fprintf(stderr, "\nrender_frames: %s; gave up after %d tries\n", why.c_str(), kTries);
        job.queue.retire(why + " (" + std::to_string(kTries) + " tries)");
        return rendered;
      }
      std::fprintf(stderr, "\nrender_frames: %s; %s again in %.1f s\n", why.c_str(),
                   in_flight.empty() ? "connecting" : "its frames go back, connecting",
                   pause.count() / 1000.0);
      std::this_thread::sleep_for(pause);
      pause *= 2;
    }
    if (job.queue.ended()) {
      job.queue.retire("");
      return rendered;
    }
  }
}

// This process's frames: the range, or its shard's slice of it.
std::optional<sweepd::console::FrameRange> own_frames(const Options& options,
                                                      const sweepd::console::FrameRange& range) {
  std::optional<sweepd::client::FrameShard> shard;
  if (!options.shard.empty()) {
    shard = sweepd::client::parse_frame_shard(options.shard);
    if (!shard) throw UsageError("--shard " + options.shard + ": expected I/N with 0 <= I < N");
  } else {
    try {
      shard = sweepd::client::frame_shard_from_environment(
          [](const char* name) -> std::optional<std::string> {
            const char* value = std::getenv(name);
            if (!value) return std::nullopt;
            return value;
          });
    } catch (const std::invalid_argument& error) {
      throw UsageError(error.what());
    }
  }
  if (!shard) return range;
  const std::optional<sweepd::console::FrameRange> mine =
      sweepd::client::shard_frames(range, *shard);
  std::printf("shard %d/%d: ", shard->index, shard->count);
  if (mine) {
    std::printf("frames %d-%d of %d-%d\n", mine->first, mine->last, range.first, range.last);
  } else {
    std::printf("no frame of %d-%d (more shards than frames)\n", range.first, range.last);
  }
  return mine;
}

int run(Options& options) {
  // The clip is read once here (each server gets these bytes) and for its frame count: the
  // range is checked, and complete frames skipped, before any server is asked. The range of
  // motion's frames depend on the model's rig: each frame past its end fails naming them.
  options.clip.read();
  const sweepd::console::FrameRange range = clip_range(options.frames, options.clip.frame_count());
  const std::vector<std::string> servers = sweepd::console::split_list(options.server);
  if (servers.empty()) throw UsageError("--server: expected HOST:PORT[,HOST:PORT...]");
  const std::optional<sweepd::console::FrameRange> mine = own_frames(options, range);
  fs::create_directories(options.out_dir);

  // Resume: only frames without a complete file are rendered; a point cache is complete or
  // rendered again whole.
  std::vector<int> todo;
  std::optional<CacheSink> cache;
  if (options.point_cache() && mine) {
    const fs::path file = cache_file(options, *mine);
    const std::string reason = fs::exists(file) ? incomplete_cache_reason(file, *mine) : "absent";
    if (!reason.empty()) {
      if (reason != "absent")
        std::fprintf(stderr,
                     "%s is not a complete cache of frames %d-%d (%s): rendering it again\n",
                     file.c_str(), mine->first, mine->last, reason.c_str());
      cache.emplace(file, options, *mine);
      for (int frame = mine->first; frame <= mine->last; ++frame) todo.push_back(frame);
    }
  }
  for (int frame = mine ? mine->first : 0; mine && !options.point_cache() && frame <= mine->last;
       ++frame) {
    const fs::path file = frame_file(options, frame);
    if (!fs::exists(file)) {
      todo.push_back(frame);
    } else if (const std::string reason = incomplete_reason(file); !reason.empty()) {
      std::fprintf(stderr, "%s is not a complete EXR (%s): rendering it again\n", file.c_str(),
                   reason.c_str());
      fs::remove(file);  // the new one is renamed into place without replacing
      todo.push_back(frame);
    }
  }
  const int total = mine ? mine->count() : 0;
  const int skipped = total - static_cast<int>(todo.size());
  const Clock::time_point start = Clock::now();
  sweepd::client::FrameQueue queue(todo, options.attempts, static_cast<int>(servers.size()));
  std::vector<int> rendered_by(servers.size(), 0);
  if (!todo.empty()) {  // else nothing to ask a server for
    sweepd::client::ModelSource model =
        options.model_file.empty()
            ? sweepd::client::ModelSource(options.model.empty() ? "mannequin" : options.model, {})
            : sweepd::client::ModelSource(
                  options.model.empty() ? sweepd::client::model_name_of_file(options.model_file)
                                        : options.model,
                  sweepd::io::read_file_bytes(options.model_file));
    Progress progress("rendering " + fs::path(options.clip.file()).stem().string(), skipped, total);
    std::once_flag reported;
    const Job job{options, model, queue, progress, reported, cache ? &*cache : nullptr};
    std::vector<std::thread> threads;
    for (std::size_t s = 0; s < servers.size(); ++s)
      threads.emplace_back([&, s] { rendered_by[s] = serve(servers[s], job); });
    for (std::thread& thread : threads) thread.join();
    if (model.uploads() > 1) {  // a server lacked the model another had: sent it again
      std::fprintf(stderr, "render_frames: uploaded %s %d times\n", options.model_file.c_str(),
                   model.uploads());
    }
  }
  const sweepd::client::FrameQueue::Tally tally = queue.tally();
  for (const std::string& line : sweepd::console::frame_failure_lines(tally.failures))
    std::fprintf(stderr, "render_frames: %s\n", line.c_str());  // a line per cause
  if (servers.size() > 1 && !todo.empty()) {
    for (std::size_t s = 0; s < servers.size(); ++s)
      std::fprintf(stderr, "%s rendered %d frames\n", servers[s].c_str(), rendered_by[s]);
  }
  if (cache && tally.failed == 0) {  // else the unfinished cache is removed
    const int points = cache->finish();
    std::printf(
        "wrote %s: frames %d-%d of %d vertices (%s, %s axes)\n", cache->file().c_str(), mine->first,
        mine->last, points, options.format == OutputFormat::kPc2 ? "PC2" : "MDD",
        options.axes == sweepd::io::PointCacheAxes::kBlender ? "Blender's Z-up" : "glTF's Y-up");
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  std::printf(
      "rendered %d, skipped %d of %d frames in %.2f s (%.2f frames/s), retried %d, "
      "failed %d\n",
      tally.rendered, skipped, total, seconds, seconds > 0 ? tally.rendered / seconds : 0.0,
      tally.retried, tally.failed);
  return tally.failed == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app("", "render_frames");
  describe(app, options);
  if (const std::optional<int> exit_code = sweepd::console::parse_command_line(app, argc, argv))
    return *exit_code;
  try {
    check_format_flags(app, options);
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
