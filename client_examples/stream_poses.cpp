// stream_poses: a sweepd client that streams a clip as poses and reports latency.
//
//   stream_poses (--bvh clip.bvh [--bvh-scale S] | --clip-from F.glb [--clip NAME|INDEX])
//                [--host 127.0.0.1] [--port 7878] [--token T | --token-file FILE]
//                [--tls [--tls-ca CA.pem] [--tls-cert C.pem --tls-key K.pem]]
//                [--model-file body.glb] [--frames N] [--flat-out] [--latest-wins] [--float16]
//
// 1. Connect, Hello (with the token; LatestWins if asked), read Welcome.
// 2. Choose the model: --model-file uploads a .glb (LoadModel with bytes); otherwise the
//    server's default "mannequin" (LoadModel by name).
// 3. Upload the clip once (UploadClip, client/clip_file_flags.h): a BVH's text, or a glTF
//    file's bytes and the animation's name (protocol 1.7); the server reads it and retargets
//    it onto the model, so this client needs no skeleton and no retargeter.
// 4. Stream the clip: one PoseFromClip per frame, naming the clip and the frame number, at the
//    clip's frame rate or --flat-out (as fast as the server answers, up to
//    Welcome.max_poses_in_flight queued).
// 5. Print poses sent/answered/dropped/errors, round-trip latency percentiles, and the
//    server's own deformation time for the model (from Stats), to show the overhead.
//
// The wire is the protocol alone (protocol/, with the blocking connection of client/).
// CMU clips are in inches: --bvh-scale defaults to 0.056444 (CMU units to metres).
// Exit codes: 0 every pose answered (or --help); 1 pose errors; 2 a bad command line (naming
// the flag: --port 12x) or a failure (unreachable server, refused, unreadable clip).
#include <algorithm>
#include <asio.hpp>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <semaphore>
#include <string>
#include <thread>
#include <vector>

#include "client/client_tls_flags.h"
#include "client/clip_file_flags.h"
#include "client/connection.h"
#include "client/token_flags.h"
#include "console/command_line.h"
#include "io/file_bytes.h"
#include "protocol/messages.h"

namespace {

namespace pb = sweepd::protocol;
using Clock = std::chrono::steady_clock;

struct Options {
  std::string host = "127.0.0.1", token, model_file;
  int port = 7878;
  sweepd::client::ClipFile clip;
  int frames = 0;  // 0: the whole clip
  bool flat_out = false, latest_wins = false, float16 = false;
  sweepd::client::ClientTls tls;
};

// The command line (console/command_line.h: --help exits 0, a bad flag or value exits 2).
void describe(CLI::App& app, Options& o) {
  app.description("Streams a clip to sweepd as poses and reports the round-trip latency.");
  sweepd::client::add_clip_file_flags(app, o.clip);
  app.add_option("--host", o.host, "sweepd's host")->capture_default_str();
  app.add_option("--port", o.port, "sweepd's port")
      ->check(sweepd::console::whole_number(1, 65535))
      ->capture_default_str();
  sweepd::client::add_token_flags(app, o.token);
  sweepd::client::add_client_tls_flags(app, o.tls);
  app.add_option("--model-file", o.model_file, "a .glb to upload (default: the mannequin)");
  app.add_option("--frames", o.frames, "stream the first N frames (0: the whole clip)")
      ->check(sweepd::console::whole_number(0, 1 << 30))
      ->capture_default_str();
  app.add_flag("--flat-out", o.flat_out, "as fast as the server answers, not at the clip's rate");
  app.add_flag("--latest-wins", o.latest_wins, "the server may drop poses it has not started");
  app.add_flag("--float16", o.float16, "positions as float16 on the wire");
}

double percentile_ms(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1))];
}

int run(Options& options) {
  options.clip.read();
  sweepd::client::Connection channel(options.host, std::to_string(options.port), options.tls);
  const std::uint32_t window =
      channel
          .hello(options.token, "stream_poses",
                 options.latest_wins ? pb::PoseDelivery::LatestWins : pb::PoseDelivery::InOrder)
          .max_poses_in_flight();

  // The model: upload a .glb, or use the server's default mannequin.
  const std::vector<std::uint8_t> glb = options.model_file.empty()
                                            ? std::vector<std::uint8_t>{}
                                            : sweepd::io::read_file_bytes(options.model_file);
  const pb::ModelInfo& info =
      channel.load_model(options.model_file.empty() ? "mannequin" : options.model_file, glb);
  const std::uint32_t model_id = info.model_id();
  std::printf("model %u: %u vertices, %u joints\n", model_id, info.vertex_count(),
              info.joint_names()->size());
  // `info` is invalid from the next receive on.
  const pb::ClipInfo& clip = sweepd::client::upload_clip_file(channel, options.clip);
  const std::string clip_id = clip.clip_id()->str();
  const double frame_time = 1.0 / clip.frames_per_second();
  const int clip_frames = static_cast<int>(clip.frame_count());
  std::printf("clip %s: %d frames at %.0f fps\n", clip.name()->c_str(), clip_frames,
              clip.frames_per_second());

  const int frames = options.frames > 0 ? std::min(options.frames, clip_frames) : clip_frames;

  // Replies are read on their own thread; `slots` bounds the poses in flight.
  std::counting_semaphore<1 << 16> slots(static_cast<std::ptrdiff_t>(window));
  std::vector<Clock::time_point> sent_at(static_cast<std::size_t>(frames) + 1);
  std::vector<double> latencies_ms;
  std::uint64_t answered = 0, dropped = 0, errors = 0;
  std::thread reader([&]() {
    for (std::uint64_t last = 0; last < static_cast<std::uint64_t>(frames);) {
      const pb::Message& message = channel.receive();
      std::uint64_t sequence = 0;
      if (const pb::PosedVertices* reply = message.body_as_PosedVertices()) {
        sequence = reply->sequence();
        latencies_ms.push_back(
            std::chrono::duration<double, std::milli>(Clock::now() - sent_at[sequence]).count());
        ++answered;
        dropped += reply->dropped_before();

      } else if (const pb::Error* error = message.body_as_Error()) {
        sequence = error->sequence();
        ++errors;
        std::fprintf(stderr, "error %s: %s\n", pb::EnumNameErrorCode(error->code()),
                     error->message()->c_str());
      }
      last = std::max(last, sequence);
      if (!options.latest_wins) slots.release();  // InOrder: every pose gets one reply
    }
  });

  flatbuffers::FlatBufferBuilder& builder = channel.builder();
  const Clock::time_point start = Clock::now();
  for (int frame = 0; frame < frames; ++frame) {
    if (!options.flat_out) {
      std::this_thread::sleep_until(start + std::chrono::duration_cast<Clock::duration>(
                                                std::chrono::duration<double>(frame * frame_time)));
    }
    pb::PoseFields fields;
    fields.model_id = model_id;
    fields.sequence = static_cast<std::uint64_t>(frame) + 1;
    fields.positions = options.float16 ? pb::PositionFormat::Float16 : pb::PositionFormat::Float32;
    if (!options.latest_wins) slots.acquire();  // LatestWins: the server drops, we never wait
    builder.Clear();
    const auto pose = pb::add_pose(builder, fields);
    const auto clip_frame = pb::CreateClipFrame(builder, builder.CreateString(clip_id),
                                                static_cast<std::uint32_t>(frame));
    const auto frame_bytes =
        pb::finish_message(builder, pb::CreatePoseFromClip(builder, pose, clip_frame));
    sent_at[fields.sequence] = Clock::now();
    channel.send(frame_bytes);
  }
  reader.join();
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  // The server's own deformation time for this model: round trip ÷ deformation = overhead.
  builder.Clear();
  channel.send(pb::finish_message(builder, pb::CreateStatsRequest(builder)));
  double deform_p50_ms = 0.0;
  for (const pb::ModelStats* model : *channel.expect<pb::Stats>().models()) {
    if (model->model_id() == model_id) deform_p50_ms = model->deform_latency()->p50_ns() * 1e-6;
  }
  channel.close("clip finished");

  std::printf("poses: sent %d, answered %llu, dropped %llu, errors %llu in %.2f s (%.0f/s)\n",
              frames, static_cast<unsigned long long>(answered),
              static_cast<unsigned long long>(dropped), static_cast<unsigned long long>(errors),
              seconds, static_cast<double>(answered) / seconds);
  std::printf("round trip ms: p50 %.3f  p90 %.3f  p99 %.3f  max %.3f\n",
              percentile_ms(latencies_ms, 0.5), percentile_ms(latencies_ms, 0.9),
              percentile_ms(latencies_ms, 0.99), percentile_ms(latencies_ms, 1.0));
  std::printf("server deformation ms: p50 %.3f (round trip p50 / deformation p50 = %.2f)\n",
              deform_p50_ms,
              deform_p50_ms > 0.0 ? percentile_ms(latencies_ms, 0.5) / deform_p50_ms : 0.0);
  return errors == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app("", "stream_poses");
  describe(app, options);
  if (const std::optional<int> exit_code = sweepd::console::parse_command_line(app, argc, argv))
    return *exit_code;
  try {
    return run(options);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "stream_poses: %s\n", error.what());
    return 2;
  }
}
