// client_examples/render_frames against the real daemon: every frame of a range becomes one
// EXR file whose positions are the library's own render of that clip frame; a rerun renders
// again exactly the files that are missing or broken and leaves the others alone; bad input
// ends the tool with a message naming it and the documented exit code; the model's range of
// motion (--range-of-motion, protocol 1.13) renders with no clip file, its range checked by the
// server.
#include <ImfInputFile.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <future>
#include <map>

#include "deform/job/deform_job.h"
#include "deform/model/pose_hash.h"
#include "gpu/egl_context.h"
#include "gpu/position_map_renderer.h"
#include "io/bvh/bvh_load.h"
#include "io/sweepbind/sweepbind.h"
#include "motion/retarget.h"
#include "tests/io/position_map_exr.h"
#include "tests/server/client_run.h"
#include "tests/server/daemon_process.h"
#include "tests/server/stored_binding.h"

namespace sweepd::test::render_frames_test {
namespace {

constexpr int kSide = 64;
constexpr int kFirst = 300, kLast = 305;  // a stretch of the clip where the body moves
constexpr float kCmuScale = 0.056444f;    // render_frames' default --bvh-scale

ClientRun run_render_frames(const std::string& arguments) {
  return run_client(std::string(SWEEPD_RENDER_FRAMES) + " " + arguments);
}

using Map = io::test_support::DecodedPositionMap;

Map read_map(const fs::path& file, int side = kSide) {
  Imf::InputFile exr(file.c_str());
  Map map = io::test_support::decode_position_map(exr);
  EXPECT_EQ(map.width, side) << file;
  EXPECT_EQ(map.height, side) << file;
  return map;
}

float largest_difference(const std::vector<float>& a, const std::vector<float>& b) {
  float largest = 0.0f;
  for (std::size_t i = 0; i < a.size(); ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
  return largest;
}

class RenderFrames : public ClipClientTest {
 protected:
  RenderFrames() : ClipClientTest("render_frames") {}
  std::string server_arguments() const {
    return "--server 127.0.0.1:" + std::to_string(daemon_->port()) + " --token t0k --bvh " +
           clip_.string();
  }
  fs::path frame_file(int frame) const {
    char name[32];
    std::snprintf(name, sizeof name, "cmu_01_01.%05d.exr", frame);
    return directory_ / "frames" / name;
  }
  // The library's own map of clip frame `frame` on the daemon's bound mannequin: retargeted
  // from the model itself (not from ModelInfo), deformed and rasterised in this process.
  Map library_map(int frame, int side) {
    if (!bound_) {
      bound_ = std::make_unique<deform::BoundModel>(
          io::load_sweepbind(stored_binding(directory_ / "store", "mannequin")));
      clip_on_model_ = std::make_unique<motion::Retargeter>(
          io::load_bvh(clip_, {.length_scale = kCmuScale}), bound_->model);
    }
    const deform::ModelRuntime runtime(*bound_);
    deform::DeformContext context;
    std::vector<glm::vec3> positions(bound_->model.vertex_count());
    std::vector<glm::vec3> normals(positions.size());
    deform::Pose pose = clip_on_model_->pose_at_frame(frame);
    deform::DeformJob job{runtime, pose};
    job.positions = positions;
    job.normals = normals;
    job.run(context);
    gpu::PositionMapRenderer renderer(context_);
    Map map{side, side, std::vector<float>(side * side * 3), std::vector<float>(side * side)};
    renderer.render({bound_->model.uvs, positions, {}, bound_->model.indices},
                    {.width = side, .height = side, .gutter_pixels = 4, .view = std::nullopt},
                    {map.positions, {}, map.coverage});
    return map;
  }
  void expect_library_map(int frame, int side = kSide) {
    SCOPED_TRACE("frame " + std::to_string(frame));
    const Map served = read_map(frame_file(frame), side);
    const Map expected = library_map(frame, side);
    // The file says what it is: the clip frame its name has (render_frames numbers its
    // requests from 1, which the header used to carry), the model the server holds, the hash
    // of the pose the library makes of that frame, in metres (issue 52 item 6).
    Imf::InputFile file(frame_file(frame).c_str());
    const io::test_support::PositionMapHeader header =
        io::test_support::read_position_map_header(file.header());
    EXPECT_EQ(header.frame, frame);
    EXPECT_EQ(header.model, "mannequin");
    EXPECT_EQ(header.pose_hash,
              io::test_support::pose_hash_text(deform::pose_hash(clip_on_model_->pose_at_frame(frame))));
    EXPECT_EQ(header.space, "object");
    EXPECT_EQ(header.units, "metres");
    // The server retargets the uploaded clip with the library on the model itself, as here:
    // the same floats. 10 µm leaves room for rasterisation on two GL contexts, far below a
    // frame-to-frame change (RendersEachFrameOnce...).
    EXPECT_LT(largest_difference(served.positions, expected.positions), 1e-5f);
    EXPECT_EQ(served.coverage, expected.coverage) << "coverage depends on the UVs alone";
  }

  // Two servers render one range; once frames arrive, `signal` hits the first server
  // (SIGKILL: it dies; SIGSTOP: it hangs, and only --timeout notices). Its frames in flight go to
  // the other server, and every frame ends up present and right.
  void render_while_one_server_fails(DaemonProcess& failing, DaemonProcess& other, int signal) {
    const fs::path frames = directory_ / "frames";
    constexpr int kLastFrame = kFirst + 99;  // long enough that the signal lands mid-run
    const auto command = [&](const std::string& servers, const fs::path& out, int last) {
      return std::string(SWEEPD_RENDER_FRAMES) + " --server " + servers + " --token t0k --bvh " +
             clip_.string() + " --frames " + std::to_string(kFirst) + "-" +
             std::to_string(last) + " -o " + out.string() + " --width 128 --height 128 --timeout 1";
    };
    // The failing server first renders two frames alone, so that it holds the model and the
    // clip when the run starts: each server binds the model and builds the clip's player at
    // upload, and on a loaded machine the other server, just as fresh, had rendered every
    // frame so far while the failing one, still preparing, held none in flight to hand back.
    const std::string failing_address = "127.0.0.1:" + std::to_string(failing.port());
    ASSERT_EQ(run_client(command(failing_address, directory_ / "warm", kFirst + 1)).exit_code, 0);
    std::future<ClientRun> run = std::async(std::launch::async, [&] {
      return run_client(command(failing_address + ",127.0.0.1:" + std::to_string(other.port()),
                                frames, kLastFrame));
    });
    while (exr_files(frames) < 10 &&
           run.wait_for(std::chrono::milliseconds(5)) != std::future_status::ready) {
    }
    const int before = exr_files(frames);
    failing.signal(signal);
    const ClientRun result = run.get();
    ASSERT_LT(before, 100) << "the signal came after the run: nothing was tested";
    ASSERT_EQ(result.exit_code, 0) << result.output << other.log();
    const std::array<int, 5> counts = render_counts(result.output);
    EXPECT_EQ(counts[0], 100) << result.output;  // rendered
    EXPECT_EQ(counts[1], 0) << result.output;    // skipped
    EXPECT_EQ(counts[2], 100) << result.output;  // total
    EXPECT_GE(counts[3], 1) << "the failing server held frames in flight\n" << result.output;
    EXPECT_EQ(counts[4], 0) << result.output;  // failed
    EXPECT_NE(result.output.find("its frames go back"), std::string::npos) << result.output;
    EXPECT_EQ(exr_files(frames), 100) << "one file per frame, no partial file left";
    for (int frame = kFirst; frame <= kLastFrame; frame += 9) expect_library_map(frame, 128);
  }

  gpu::Context context_;
  std::unique_ptr<deform::BoundModel> bound_;
  std::unique_ptr<motion::Retargeter> clip_on_model_;
};

TEST_F(RenderFrames, RendersEachFrameOnceAndAgainOnlyWhenMissingOrBroken) {
  const std::string arguments = server_arguments() + " --frames " + std::to_string(kFirst) + "-" +
                                std::to_string(kLast) + " -o " + (directory_ / "frames").string() +
                                " --width 64 --height 64";
  const ClientRun first = run_render_frames(arguments);
  ASSERT_EQ(first.exit_code, 0) << first.output << daemon_->log();
  EXPECT_EQ(render_counts(first.output), (std::array<int, 5>{6, 0, 6, 0, 0})) << first.output;
  // Once per job, the name the server holds the model under (issue 48 item 5) and what the
  // clip leaves unmapped on it (protocol 1.12: CMU drives none of the mannequin's fingers).
  const std::string held = "render_frames: model 'mannequin' (id " +
                           std::to_string(daemon_->model_id("mannequin")) + ") on ";
  EXPECT_NE(first.output.find(held), std::string::npos) << first.output;
  EXPECT_EQ(first.output.find(held, first.output.find(held) + 1), std::string::npos)
      << first.output;
  EXPECT_NE(first.output.find("on model 'mannequin': model joints the clip leaves without motion"),
            std::string::npos)
      << first.output;
  EXPECT_NE(daemon_->log().find("\"clip_uploaded\""), std::string::npos)
      << "frames are asked for by clip id and number: the server retargets";
  std::map<int, fs::file_time_type> written;
  for (int frame = kFirst; frame <= kLast; ++frame) {
    ASSERT_TRUE(fs::exists(frame_file(frame))) << frame_file(frame);
    expect_library_map(frame);
    written[frame] = fs::last_write_time(frame_file(frame));
  }
  // The check can fail: two frames of the range are further apart than its tolerance.
  EXPECT_GT(largest_difference(read_map(frame_file(kFirst)).positions,
                               read_map(frame_file(kLast)).positions),
            1e-3f);

  const int deleted = kFirst + 2, truncated = kFirst + 4;
  fs::remove(frame_file(deleted));
  fs::resize_file(frame_file(truncated), fs::file_size(frame_file(truncated)) / 2);
  const ClientRun second = run_render_frames(arguments);
  ASSERT_EQ(second.exit_code, 0) << second.output << daemon_->log();
  EXPECT_EQ(render_counts(second.output), (std::array<int, 5>{2, 4, 6, 0, 0})) << second.output;
  EXPECT_NE(
      second.output.find(frame_file(truncated).filename().string() + " is not a complete EXR"),
      std::string::npos)
      << second.output;
  for (int frame = kFirst; frame <= kLast; ++frame) {
    if (frame == deleted || frame == truncated) {
      expect_library_map(frame);
    } else {
      EXPECT_EQ(fs::last_write_time(frame_file(frame)), written[frame]) << "frame " << frame;
    }
  }
  // Nothing half-written is left beside the frames.
  int files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(directory_ / "frames")) ++files;
  EXPECT_EQ(files, 6);

  // With every frame complete there is nothing to ask: no server needed (port 1: none there).
  const ClientRun third = run_render_frames(
      "--server 127.0.0.1:1 --bvh " + clip_.string() + " --frames " + std::to_string(kFirst) + "-" +
      std::to_string(kLast) + " -o " + (directory_ / "frames").string());
  EXPECT_EQ(third.exit_code, 0) << third.output;
  EXPECT_EQ(render_counts(third.output), (std::array<int, 5>{0, 6, 6, 0, 0})) << third.output;
}

TEST_F(RenderFrames, ShardsRenderTheirSlicesAndTogetherTheRangeOnce) {
  const std::string arguments = server_arguments() + " --frames " + std::to_string(kFirst) + "-" +
                                std::to_string(kLast) + " -o " + (directory_ / "frames").string() +
                                " --width 64 --height 64";
  const ClientRun first = run_render_frames(arguments + " --shard 0/2");
  ASSERT_EQ(first.exit_code, 0) << first.output << daemon_->log();
  EXPECT_NE(first.output.find("shard 0/2: frames 300-302 of 300-305"), std::string::npos)
      << first.output;
  EXPECT_EQ(render_counts(first.output), (std::array<int, 5>{3, 0, 3, 0, 0})) << first.output;
  for (int frame = kFirst; frame <= kLast; ++frame)
    EXPECT_EQ(fs::exists(frame_file(frame)), frame <= 302) << "frame " << frame;

  // A Kubernetes Indexed Job's pod: the index from Kubernetes, the count from the Job's env.
  const ClientRun second = run_client("JOB_COMPLETION_INDEX=1 JOB_COMPLETIONS=2 " +
                                      std::string(SWEEPD_RENDER_FRAMES) + " " + arguments);
  ASSERT_EQ(second.exit_code, 0) << second.output << daemon_->log();
  EXPECT_NE(second.output.find("shard 1/2: frames 303-305 of 300-305"), std::string::npos)
      << second.output;
  EXPECT_EQ(render_counts(second.output), (std::array<int, 5>{3, 0, 3, 0, 0})) << second.output;
  for (int frame = kFirst; frame <= kLast; ++frame) expect_library_map(frame);

  const ClientRun past = run_render_frames(arguments + " --shard 2/2");
  EXPECT_EQ(past.exit_code, 2);
  EXPECT_NE(past.output.find("--shard 2/2: expected I/N with 0 <= I < N"), std::string::npos)
      << past.output;
  const ClientRun half =
      run_client("JOB_COMPLETION_INDEX=1 " + std::string(SWEEPD_RENDER_FRAMES) + " " + arguments);
  EXPECT_EQ(half.exit_code, 2);
  EXPECT_NE(half.output.find("JOB_COMPLETIONS is not"), std::string::npos) << half.output;
}

TEST_F(RenderFrames, AKilledServersFramesAreRenderedByTheOther) {
  const fs::path other_directory = fresh_directory("render_frames_other");
  DaemonProcess other(other_directory, {"--token", "t0k"});
  ASSERT_TRUE(other.running()) << other.log();
  render_while_one_server_fails(*daemon_, other, SIGKILL);
  fs::remove_all(other_directory);
}

TEST_F(RenderFrames, AHungServersFramesTimeOutAndAreRenderedByTheOther) {
  const fs::path other_directory = fresh_directory("render_frames_other");
  DaemonProcess other(other_directory, {"--token", "t0k"});
  ASSERT_TRUE(other.running()) << other.log();
  render_while_one_server_fails(*daemon_, other, SIGSTOP);
  daemon_->signal(SIGCONT);
  fs::remove_all(other_directory);
}

TEST_F(RenderFrames, AFramesServerErrorNamesTheFrameAndLeavesNoFile) {
  // A second daemon that answers every PositionMapRequest with NotAvailable.
  const fs::path other = fresh_directory("render_frames_no_maps");
  DaemonProcess no_maps(other, {"--position-maps", "0"});
  ASSERT_TRUE(no_maps.running()) << no_maps.log();
  const ClientRun run =
      run_render_frames("--server 127.0.0.1:" + std::to_string(no_maps.port()) + " --bvh " +
                        clip_.string() + " --frames 7-9 -o " + (directory_ / "frames").string());
  EXPECT_EQ(run.exit_code, 1);
  // One cause for the three frames, said once with their count (issue 52 item 6).
  EXPECT_NE(run.output.find("render_frames: 3 frames failed (7-9): 127.0.0.1:" +
                            std::to_string(no_maps.port()) + ": server error NotAvailable"),
            std::string::npos)
      << run.output;
  EXPECT_EQ(run.output.find("frame 8 failed"), std::string::npos) << run.output;
  int files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(directory_ / "frames")) ++files;
  EXPECT_EQ(files, 0) << "neither a frame nor a partial file";
  fs::remove_all(other);
}

TEST_F(RenderFrames, TheModelsRangeOfMotionRendersWithoutAClipFile) {
  const std::string arguments = "--server 127.0.0.1:" + std::to_string(daemon_->port()) +
                                " --token t0k --range-of-motion --width 16 --height 16 -o " +
                                (directory_ / "frames").string() + " --frames ";
  const ClientRun peak = run_render_frames(arguments + "15-15");
  ASSERT_EQ(peak.exit_code, 0) << peak.output << daemon_->log();
  EXPECT_TRUE(fs::exists(directory_ / "frames/range_of_motion.00015.exr")) << peak.output;
  // Its frames are the model's rig's (1441 for the mannequin): the server refuses one past them.
  const ClientRun past = run_render_frames(arguments + "1441-1441");
  EXPECT_EQ(past.exit_code, 1) << past.output;
  EXPECT_NE(past.output.find("frame 1441 failed: "), std::string::npos) << past.output;
  EXPECT_NE(past.output.find("past the clip's last frame 1440"), std::string::npos) << past.output;
  // Many frames past it: one line with their count, "frame N" for each one's own number, not a
  // line per frame (issue 52 item 6).
  const ClientRun many = run_render_frames(arguments + "1430-1469");
  EXPECT_EQ(many.exit_code, 1) << many.output;
  const std::size_t line = many.output.find(
      "render_frames: 29 frames failed (1441-1469): server error InvalidArgument: clip 'range of "
      "motion' on model ");
  ASSERT_NE(line, std::string::npos) << many.output;
  EXPECT_NE(many.output.find(": frame N is past the clip's last frame 1440", line), std::string::npos)
      << many.output;
  EXPECT_EQ(many.output.find("frame 1450"), std::string::npos) << many.output;
  EXPECT_NE(many.output.find("rendered 11, skipped 0 of 40 frames"), std::string::npos)
      << many.output;
}

TEST_F(RenderFrames, BadInputIsNamedWithItsExitCode) {
  const std::string out = " -o " + (directory_ / "frames").string();
  const ClientRun unknown_model =
      run_render_frames(server_arguments() + " --frames 0-1 --model nobody" + out);
  EXPECT_EQ(unknown_model.exit_code, 1);
  EXPECT_NE(unknown_model.output.find("UnknownModel"), std::string::npos) << unknown_model.output;

  const ClientRun bad_range = run_render_frames(server_arguments() + " --frames 9-3" + out);
  EXPECT_EQ(bad_range.exit_code, 2);
  EXPECT_NE(bad_range.output.find("--frames 9-3"), std::string::npos) << bad_range.output;

  const ClientRun past_the_clip =
      run_render_frames(server_arguments() + " --frames 0-1000000" + out);
  EXPECT_EQ(past_the_clip.exit_code, 2);
  EXPECT_NE(past_the_clip.output.find("the clip has frames 0-"), std::string::npos)
      << past_the_clip.output;

  const ClientRun wrong_token =
      run_render_frames("--server 127.0.0.1:" + std::to_string(daemon_->port()) +
                        " --token wrong --bvh " + clip_.string() + " --frames 0-1" + out);
  EXPECT_EQ(wrong_token.exit_code, 1);
  EXPECT_NE(wrong_token.output.find("AuthFailed"), std::string::npos) << wrong_token.output;

  // The token from a file's first line (a mounted Secret), or a usage error naming the file.
  const fs::path token_file = directory_ / "token";
  std::ofstream(token_file) << "t0k\n";
  const ClientRun from_file =
      run_render_frames("--server 127.0.0.1:" + std::to_string(daemon_->port()) + " --token-file " +
                        token_file.string() + " --bvh " + clip_.string() +
                        " --frames 0-0 --width 16 --height 16" + out);
  EXPECT_EQ(from_file.exit_code, 0) << from_file.output;
  const ClientRun no_file =
      run_render_frames("--server 127.0.0.1:1 --token-file " + (directory_ / "absent").string() +
                        " --bvh " + clip_.string() + " --frames 0-1" + out);
  EXPECT_EQ(no_file.exit_code, 2) << no_file.output;
  EXPECT_NE(no_file.output.find("absent: cannot read the file"), std::string::npos)
      << no_file.output;
  const ClientRun both = run_render_frames(server_arguments() + " --token-file " +
                                           token_file.string() + " --frames 0-1" + out);
  EXPECT_EQ(both.exit_code, 2) << both.output;
  EXPECT_NE(both.output.find("excludes"), std::string::npos) << both.output;
  fs::remove(frame_file(0));

  // Port 1: nothing listens there (a privileged port no test runs a server on).
  const ClientRun unreachable =
      run_render_frames("--server 127.0.0.1:1 --bvh " + clip_.string() + " --frames 0-1" + out);
  EXPECT_EQ(unreachable.exit_code, 1);
  EXPECT_NE(unreachable.output.find("cannot connect to sweepd at 127.0.0.1:1"), std::string::npos)
      << unreachable.output;
  EXPECT_FALSE(fs::exists(frame_file(0)));
}

}  // namespace
}  // namespace sweepd::test::render_frames_test
