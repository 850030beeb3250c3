// stream_poses: a sweepd client that streams a clip as poses and reports latency.
//
//   stream_poses (--bvh clip.bvh [--bvh-scale S] | --clip-from F.glb [--clip NAME|INDEX] |
//                 --range-of-motion)
//                [--host 127.0.0.1] [--port 7878 | --unix PATH [--shared-memory]]
//                [--token T | --token-file FILE]
//                [--tls [--tls-ca CA.pem] [--tls-cert C.pem --tls-key K.pem]]
//                [--model NAME] [--model-file body.glb] [--frames N] [--flat-out]
//                [--latest-wins] [--float16]
//
// 1. Connect (TCP, or sweepd's Unix socket with --unix), Hello (with the token; LatestWins if
//    asked), read Welcome. --shared-memory (protocol 1.10, on the Unix socket): the replies are
//    written into a region shared with sweepd (one slot per pose in flight) instead of sent.
// 2. Choose the model (client/model_source.h): --model-file uploads a .glb (LoadModel with
//    bytes) under --model NAME, else under the file's base name ("body" for dir/body.glb, the
//    name every client and every restart finds it by); otherwise the server's model --model
//    (default: its "mannequin"; LoadModel by name). Prints the name the server holds it under.
// 3. Upload the clip once (UploadClip, client_examples/clip_file_flags.h): a BVH's text, or a glTF
//    file's bytes and the animation's name (protocol 1.7); the server reads it and retargets
//    it onto the model, so this client needs no skeleton and no retargeter. Its warnings go to
//    stderr: the reader's, and (1.12, the upload names the model) the clip joints that drive
//    no model joint and the model joints left without motion. --range-of-motion (1.13) sends
//    no clip: the server builds the model's range of motion and plays it on its own joints.
// 4. Stream the clip: one PoseFromClip per frame, naming the clip and the frame number, at the
//    clip's frame rate or --flat-out (as fast as the server answers, up to
//    Welcome.max_poses_in_flight queued).
// 5. A lost connection (the daemon restarted, HAProxy moved to another replica; or the server
//    answers a pose with UnknownModel/UnknownClip) is made again (client/reconnect.h) and set
//    up again: the model goes by its content id and is uploaded again only to a server that
//    lacks it (client/model_source.h), the clip is uploaded again. InOrder, each pose it left
//    unanswered is asked for again, once (a pose unanswered twice is an error); LatestWins, they
//    count as dropped. The report then says how many times it connected again.
// 6. Print the poses that failed, a line per cause with their count and frames, then poses
//    sent/answered/dropped/errors, round-trip latency percentiles, and the server's own
//    deformation time for the model (from Stats), to show the overhead.
//
// The wire is the protocol alone (protocol/, with the blocking connection of client/).
// CMU clips are in inches: --bvh-scale defaults to 0.056444 (CMU units to metres).
// Exit codes: 0 every pose answered (or --help); 1 pose errors; 2 a bad command line (naming
// the flag: --port 12x) or a failure (unreachable server, refused, unreadable clip).
#include <algorithm>
#include <asio.hpp>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <semaphore>
#include <string>
#include <thread>
#include <vector>

#include "client/bind_warnings.h"
#include "client/client_tls_flags.h"
#include "client/connection.h"
#include "client/model_source.h"
#include "client/pose_error.h"
#include "client/reconnect.h"
#include "client/token_flags.h"
#include "client_examples/clip_file_flags.h"
#include "console/command_line.h"
#include "console/frame_failures.h"
#include "io/files/file_bytes.h"
#include "protocol/messages.h"

namespace {

namespace pb = sweepd::protocol;
using Clock = std::chrono::steady_clock;

struct Options {
  std::string host = "127.0.0.1", token, model, model_file;
  int port = 7878;
  sweepd::client_examples::ClipFile clip;
  int frames = 0;  // 0: the whole clip
  bool flat_out = false, latest_wins = false, float16 = false;
  std::string unix_socket;     // empty: TCP to host:port
  bool shared_memory = false;  // replies in a region shared with sweepd (needs unix_socket)
  sweepd::client::ClientTls tls;
};

// The command line (console/command_line.h: --help exits 0, a bad flag or value exits 2).
void describe(CLI::App& app, Options& o) {
  app.description("Streams a clip to sweepd as poses and reports the round-trip latency.");
  sweepd::client_examples::add_clip_file_flags(app, o.clip);
  app.add_option("--host", o.host, "sweepd's host")->capture_default_str();
  app.add_option("--port", o.port, "sweepd's port")
      ->check(sweepd::console::whole_number(1, 65535))
      ->capture_default_str();
  sweepd::client::add_token_flags(app, o.token);
  sweepd::client::add_client_tls_flags(app, o.tls);
  app.add_option("--model", o.model,
                 "with --model-file: the name to upload it under (default: the file's base "
                 "name); without: a model the server has (default: mannequin)");
  app.add_option("--model-file", o.model_file, "a .glb to upload (default: the mannequin)");
  app.add_option("--frames", o.frames, "stream the first N frames (0: the whole clip)")
      ->check(sweepd::console::whole_number(0, 1 << 30))
      ->capture_default_str();
  app.add_flag("--flat-out", o.flat_out, "as fast as the server answers, not at the clip's rate");
  app.add_flag("--latest-wins", o.latest_wins, "the server may drop poses it has not started");
  CLI::Option* float16 = app.add_flag("--float16", o.float16, "positions as float16 on the wire");
  CLI::Option* unix_socket = app.add_option("--unix", o.unix_socket,
                                            "sweepd's Unix socket (its --unix-socket) instead of "
                                            "--host and --port");
  app.add_flag("--shared-memory", o.shared_memory,
               "replies written by sweepd into memory shared with it, not sent (float32)")
      ->needs(unix_socket)
      ->excludes(float16);
}

double percentile_ms(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1))];
}

// What a connection is set up with, and what its set-up answered (the same on every server:
// handles and clip ids come from content).
struct Session {
  std::uint32_t window = 1, model_id = 0;
  std::uint64_t slot_bytes = 0;  // --shared-memory: one pose's positions in the region
  std::string clip_id;
  double frame_time = 0.0;
  int clip_frames = 0;
};

// The stream across connections: when each frame was sent, how often, whether it is settled
// (answered, dropped or failed), and the counts for the report.
struct Stream {
  explicit Stream(int frames)
      : sent_at(static_cast<std::size_t>(frames)),
        tries(static_cast<std::size_t>(frames), 0),
        settled(static_cast<std::size_t>(frames), 0) {}
  std::mutex mutex;
  std::vector<Clock::time_point> sent_at;
  std::vector<int> tries;
  std::vector<char> settled;
  std::vector<double> latencies_ms;
  std::uint64_t answered = 0, dropped = 0, errors = 0;
  std::map<int, std::string> failures;  // frame -> why; said per cause at the end
};

// Whether an Error for a pose means this connection cannot go on: the server no longer has
// the model or clip (a restarted daemon, a replica with a store of its own; set up again, the
// model is uploaded again) or closes.
bool ends_connection(const pb::Error& error) {
  return error.fatal() || error.code() == pb::ErrorCode::UnknownModel ||
         error.code() == pb::ErrorCode::UnknownClip;
}

// One connection's part of the stream: `again` (frames a lost connection left unanswered, sent
// at once), then frames from `next` on at the clip's rate (or --flat-out). Returns true when
// every frame it sent was settled; false when the connection was lost (or ended by the
// server, ends_connection), with `next` at the first frame it did not send.
bool stream_on(sweepd::client::Connection& channel, const Options& options, const Session& session,
               Stream& stream, const std::vector<int>& again, int& next, int frames,
               Clock::time_point start) {
  const bool in_order = !options.latest_wins;
  // Replies are read on their own thread; `slots` bounds the poses in flight (InOrder).
  std::counting_semaphore<1 << 16> slots(static_cast<std::ptrdiff_t>(session.window));
  std::atomic<bool> lost = false;
  const auto lose = [&](const std::string& why) {
    if (lost.exchange(true)) return;
    std::fprintf(stderr, "stream_poses: %s\n", why.c_str());
    channel.abort();  // ends a receive or send blocked in the other thread
    slots.release(static_cast<std::ptrdiff_t>(session.window));
  };
  // InOrder: every pose gets one reply; LatestWins: the newest pose is always answered.
  const std::size_t expected = again.size() + static_cast<std::size_t>(frames - next);
  const std::uint64_t newest = static_cast<std::uint64_t>(frames);  // its sequence
  // The first frame this connection sends (read here: the sender moves `next` on).
  const std::size_t first_frame = static_cast<std::size_t>(again.empty() ? next : again.front());
  std::thread reader([&]() {
    std::size_t oldest = first_frame;
    for (std::size_t replies = 0; replies < expected && !lost;) {
      std::uint64_t sequence = 0;
      try {
        const pb::Message& message = channel.receive();
        const std::lock_guard lock(stream.mutex);
        if (const pb::PosedVertices* reply = message.body_as_PosedVertices()) {
          sequence = reply->sequence();
          if (sequence < 1 || sequence > stream.settled.size())
            throw std::runtime_error("a reply to pose " + std::to_string(sequence) +
                                     ", which was not sent");
          if (options.shared_memory && channel.shared_positions(*reply).empty())
            throw std::runtime_error("the reply to pose " + std::to_string(sequence) +
                                     " is not in the shared region");
          const std::size_t frame = sequence - 1;
          stream.latencies_ms.push_back(
              std::chrono::duration<double, std::milli>(Clock::now() - stream.sent_at[frame])
                  .count());
          ++stream.answered;
          stream.dropped += reply->dropped_before();
          // Replies come in the order sent (frames ascending on a connection): LatestWins, the
          // poses before this one that were not answered were dropped, and are counted.
          for (; !in_order && oldest < frame; ++oldest) stream.settled[oldest] = 1;
          stream.settled[frame] = 1;
        } else if (const pb::Error* error = message.body_as_Error()) {
          sequence = error->sequence();
          const std::string why = sweepd::client::pose_error_cause(*error);
          if (ends_connection(*error)) {
            lose(why);
            break;
          }
          ++stream.errors;
          if (sequence >= 1 && sequence <= stream.settled.size()) {
            stream.settled[sequence - 1] = 1;
            stream.failures[static_cast<int>(sequence - 1)] = why;
          } else {  // no frame to file it under
            std::fprintf(stderr, "%s\n", why.c_str());
          }
        } else {  // a Bye (the server drains, then closes), or else no pose's reply
          const pb::Bye* bye = message.body_as_Bye();
          lose(std::string("the server said Bye") +
               (bye && bye->reason() ? ": " + bye->reason()->str() : ""));
          break;
        }
      } catch (const std::exception& error) {  // lost, or a frame that is not the protocol's
        lose(error.what());
        break;
      }
      ++replies;
      if (in_order) slots.release();
      if (!in_order && sequence == newest) break;
    }
  });

  flatbuffers::FlatBufferBuilder& builder = channel.builder();
  const auto send = [&](int frame) {
    pb::PoseFields fields;
    fields.model_id = session.model_id;
    fields.sequence = static_cast<std::uint64_t>(frame) + 1;
    fields.positions = options.float16 ? pb::PositionFormat::Float16 : pb::PositionFormat::Float32;
    // A slot per pose in flight: a frame's slot is written again only `window` frames later.
    if (options.shared_memory)
      fields.shared_offset =
          static_cast<std::uint64_t>(frame) % session.window * session.slot_bytes;
    builder.Clear();
    const auto pose = pb::add_pose(builder, fields);
    const auto clip_frame = pb::CreateClipFrame(builder, builder.CreateString(session.clip_id),
                                                static_cast<std::uint32_t>(frame));
    const auto frame_bytes =
        pb::finish_message(builder, pb::CreatePoseFromClip(builder, pose, clip_frame));
    {
      const std::lock_guard lock(stream.mutex);
      stream.sent_at[static_cast<std::size_t>(frame)] = Clock::now();
      ++stream.tries[static_cast<std::size_t>(frame)];
    }
    try {
      channel.send(frame_bytes);
    } catch (const sweepd::client::ConnectionLost& error) {
      lose(error.what());
    }
  };
  for (const int frame : again) {
    if (in_order) slots.acquire();  // LatestWins: the server drops, we never wait
    if (lost) break;
    send(frame);
  }
  for (; next < frames && !lost; ++next) {
    if (!options.flat_out) {
      std::this_thread::sleep_until(start +
                                    std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(next * session.frame_time)));
    }
    if (in_order) slots.acquire();
    if (lost) break;
    send(next);
  }
  reader.join();
  return !lost;
}

// The frames sent and not settled when a connection was lost: InOrder, each is asked for again
// once on the next connection (returned), and a frame lost twice is an error; LatestWins, newer
// poses replace them, so they count as dropped.
std::vector<int> unsettled(Stream& stream, const Options& options, int next) {
  std::vector<int> again;
  for (int frame = 0; frame < next; ++frame) {
    const auto f = static_cast<std::size_t>(frame);
    if (stream.settled[f]) continue;
    if (!options.latest_wins && stream.tries[f] < 2) {
      again.push_back(frame);
      continue;
    }
    stream.settled[f] = 1;
    if (options.latest_wins) {
      ++stream.dropped;
    } else {
      ++stream.errors;
      stream.failures[frame] = "unanswered on two connections";
    }
  }
  return again;
}

int run(Options& options) {
  options.clip.read();
  const std::string address = options.unix_socket.empty()
                                  ? options.host + ":" + std::to_string(options.port)
                                  : "unix:" + options.unix_socket;
  // The model: a .glb uploaded, or the server's default mannequin; asked for by content id
  // after the first answer, so a server that lacks it (restarted, another replica) gets it
  // again (client/model_source.h).
  sweepd::client::ModelSource model =
      options.model_file.empty()
          ? sweepd::client::ModelSource(options.model.empty() ? "mannequin" : options.model, {})
          : sweepd::client::ModelSource(options.model.empty()
                                            ? sweepd::client::model_name_of_file(options.model_file)
                                            : options.model,
                                        sweepd::io::read_file_bytes(options.model_file));
  Session session;
  bool first = true;
  const auto set_up = [&](sweepd::client::Connection& channel) {
    session.window = std::max(1u, channel
                                      .hello(options.token, "stream_poses",
                                             options.latest_wins ? pb::PoseDelivery::LatestWins
                                                                 : pb::PoseDelivery::InOrder)
                                      .max_poses_in_flight());
    const pb::ModelInfo& info = model.load(channel);
    session.model_id = info.model_id();
    session.slot_bytes = std::uint64_t{info.vertex_count()} * 3 * sizeof(float);
    if (first) {
      std::printf("model '%s' (id %u): %u vertices, %u joints\n", info.name()->c_str(),
                  session.model_id, info.vertex_count(), info.joint_names()->size());
      // (protocol 1.14) where the server's self-check found the sweep worse than skinning.
      sweepd::client::print_bind_warnings(stderr, info);
    }
    if (options.shared_memory) channel.map_shared_memory(session.window * session.slot_bytes);
    // `info` is invalid from the next receive on.
    const pb::ClipInfo& clip =
        sweepd::client_examples::upload_clip_file(channel, options.clip, session.model_id);
    session.clip_id = clip.clip_id()->str();
    session.frame_time = 1.0 / clip.frames_per_second();
    session.clip_frames = static_cast<int>(clip.frame_count());
    if (first) {
      std::printf("clip %s: %d frames at %.0f fps\n", clip.name()->c_str(), session.clip_frames,
                  clip.frames_per_second());
      // The reader's warnings and (protocol 1.12) what playing it on the model leaves unmapped.
      if (clip.warnings())
        for (const flatbuffers::String* warning : *clip.warnings())
          std::fprintf(stderr, "warning: %s: %s\n", options.clip.file().c_str(), warning->c_str());
    }
    first = false;
  };
  auto channel = std::make_unique<sweepd::client::Connection>(address, options.tls);
  set_up(*channel);

  const int frames =
      options.frames > 0 ? std::min(options.frames, session.clip_frames) : session.clip_frames;
  Stream stream(frames);
  std::vector<int> again;
  int next = 0, reconnections = 0;
  const Clock::time_point start = Clock::now();
  // A lost connection (the daemon restarted, HAProxy moved us): connect again and go on with
  // the frames not answered (client/reconnect.h).
  while (!stream_on(*channel, options, session, stream, again, next, frames, start)) {
    again = unsettled(stream, options, next);
    ++reconnections;
    channel = sweepd::client::reconnect(address, options.tls, set_up);
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  // The server's own deformation time for this model: round trip ÷ deformation = overhead.
  flatbuffers::FlatBufferBuilder& builder = channel->builder();
  builder.Clear();
  channel->send(pb::finish_message(builder, pb::CreateStatsRequest(builder)));
  double deform_p50_ms = 0.0;
  for (const pb::ModelStats* stats : *channel->expect<pb::Stats>().models()) {
    if (stats->model_id() == session.model_id)
      deform_p50_ms = stats->deform_latency()->p50_ns() * 1e-6;
  }
  channel->close("clip finished");

  for (const std::string& line : sweepd::console::frame_failure_lines(stream.failures))
    std::fprintf(stderr, "stream_poses: %s\n", line.c_str());  // a line per cause
  if (reconnections > 0) {
    std::printf("reconnected %d times, model uploaded %d times\n", reconnections, model.uploads());
  }
  const std::vector<double>& latencies_ms = stream.latencies_ms;
  std::printf("poses: sent %d, answered %llu, dropped %llu, errors %llu in %.2f s (%.0f/s)\n",
              frames, static_cast<unsigned long long>(stream.answered),
              static_cast<unsigned long long>(stream.dropped),
              static_cast<unsigned long long>(stream.errors), seconds,
              static_cast<double>(stream.answered) / seconds);
  std::printf("round trip ms: p50 %.3f  p90 %.3f  p99 %.3f  max %.3f\n",
              percentile_ms(latencies_ms, 0.5), percentile_ms(latencies_ms, 0.9),
              percentile_ms(latencies_ms, 0.99), percentile_ms(latencies_ms, 1.0));
  std::printf("server deformation ms: p50 %.3f (round trip p50 / deformation p50 = %.2f)\n",
              deform_p50_ms,
              deform_p50_ms > 0.0 ? percentile_ms(latencies_ms, 0.5) / deform_p50_ms : 0.0);
  return stream.errors == 0 ? 0 : 1;
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
