// sweepd --collision: two daemons over localhost, one finding folding's and contact's pairs on its
// GPU thread (llvmpipe here), one on the CPU, return the same vertices for the shared male with
// folding, protrusion and whole-body contact — elbow and knee flexed 150°, and frames of CMU
// clips 01_01 and 01_03 — and
// say which backend they use, with its stage times, in Stats; with one deformation worker, a
// plain pose of a second connection is answered while the first waits on the GPU thread.
// Without an EGL driver (libglvnd told to load no vendor, as tests/gpu/egl_context_test.cpp
// does) `--collision gpu` is a start-up error naming the problem (exit 2) and `auto` serves on
// the CPU, saying why in its log.
// The clips are sampled every 50th frame, as issue 13's acceptance asks (147 poses);
// SWEEPD_COLLISION_FRAME_STEP=N samples every Nth instead.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <chrono>
#include <cstdlib>
#include <memory>
#include <thread>

#include "deform/model/joint_flexion.h"
#include "io/bvh/bvh_load.h"
#include "io/gltf/gltf_load.h"
#include "motion/retarget.h"
#include "tests/server/daemon_process.h"
#include "tests/server/pose_frames.h"

namespace sweepd::test {
namespace {

namespace pb = sweepd::protocol;

// What libglvnd reads to find EGL vendors: a file that does not exist leaves it none.
constexpr char kNoEglVendor[] = "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/sweepd_no_vendor.json";

// The environment of the daemons started inside its scope has no EGL driver.
class WithoutEglDriver {
 public:
  WithoutEglDriver() {
    ::putenv(const_cast<char*>(kNoEglVendor));
    if (const char* dirs = std::getenv("__EGL_VENDOR_LIBRARY_DIRS")) dirs_ = dirs;
    ::unsetenv("__EGL_VENDOR_LIBRARY_DIRS");
  }
  ~WithoutEglDriver() {
    ::unsetenv("__EGL_VENDOR_LIBRARY_FILENAMES");
    if (!dirs_.empty()) ::setenv("__EGL_VENDOR_LIBRARY_DIRS", dirs_.c_str(), 1);
  }

 private:
  std::string dirs_;
};

const pb::Stats* request_stats(FrameClient& client) {
  flatbuffers::FlatBufferBuilder builder;
  client.send_bytes(pb::finish_message(builder, pb::CreateStatsRequest(builder), 99));
  return client.receive_as<pb::Stats>();
}

// A daemon with the given --collision, holding the shared male (uploaded), and a session.
struct MaleDaemon {
  MaleDaemon(const std::string& backend, const fs::path& male)
      : directory(fresh_directory("collision_" + backend)),
        daemon(directory, {"--collision", backend, "--position-maps", "0", "--mannequin-vertices",
                           "2000", "--worker-threads", "1"}) {
    if (!daemon.running()) return;
    client = std::make_unique<FrameClient>(daemon.port());
    if (client->hello("") == nullptr) return;
    const std::vector<std::uint8_t> glb = read_bytes(male);
    flatbuffers::FlatBufferBuilder builder;
    client->send_bytes(
        pb::finish_message(builder, pb::CreateLoadModelDirect(builder, "male", &glb), 2));
    if (const pb::ModelInfo* info = client->receive_as<pb::ModelInfo>())
      model_id = info->model_id();
  }
  ~MaleDaemon() { fs::remove_all(directory); }

  fs::path directory;
  DaemonProcess daemon;
  std::unique_ptr<FrameClient> client;
  std::uint32_t model_id = 0;
};

bool send_male_pose(MaleDaemon& served, const deform::Pose& pose, std::uint64_t sequence,
                    pb::Features features) {
  const std::vector<pb::Quat> wire = to_wire(pose.local_rotations);
  pb::PoseFields fields = pose_fields(served.model_id, sequence, wire);
  fields.root_translation =
      pb::Vec3(pose.root_translation.x, pose.root_translation.y, pose.root_translation.z);
  fields.features = features;
  return send_pose(*served.client, fields);
}

std::vector<float> receive_positions(MaleDaemon& served) {
  const pb::PosedVertices* reply = served.client->receive_as<pb::PosedVertices>();
  if (reply == nullptr || reply->positions_f32() == nullptr) return {};
  return {reply->positions_f32()->begin(), reply->positions_f32()->end()};
}

float largest_difference(const std::vector<float>& a, const std::vector<float>& b) {
  float largest = 0.0f;
  for (std::size_t i = 0; i < a.size(); ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
  return largest;
}

TEST(DaemonCollisionBackend, GpuAndCpuGiveTheSameVerticesOnTheMaleAndItsClips) {
  const fs::path data(SWEEPD_SHARED_DATA);
  const fs::path male_file = data / "models/makehuman_male_cmu.glb";
  if (!fs::exists(male_file)) GTEST_SKIP() << "shared data absent: " << male_file;
  MaleDaemon gpu("gpu", male_file), cpu("cpu", male_file);
  ASSERT_NE(gpu.model_id, 0u) << gpu.daemon.log();
  ASSERT_NE(cpu.model_id, 0u) << cpu.daemon.log();
  EXPECT_NE(gpu.daemon.log().find(R"("backend":"gpu","choice":"gpu")"), std::string::npos)
      << gpu.daemon.log();

  const deform::Model male = io::load_gltf(male_file);
  std::vector<std::pair<std::string, deform::Pose>> poses;
  {
    // The male's left elbow and knee flexed to 150° (tests/deform/shared_male.h's pose).
    deform::Pose bent = deform::rest_pose(male.skeleton);
    const glm::vec3 shoulder(male.skeleton.world_rest_matrices()[male.skeleton.find("LeftArm")][3]);
    const glm::vec3 elbow(
        male.skeleton.world_rest_matrices()[male.skeleton.find("LeftForeArm")][3]);
    const glm::vec3 axis = glm::normalize(glm::cross(glm::normalize(elbow - shoulder), {0, 0, 1}));
    deform::flex_joint(male.skeleton, bent, male.skeleton.find("LeftForeArm"), axis, 150.0f);
    deform::flex_joint(male.skeleton, bent, male.skeleton.find("LeftLeg"), {1, 0, 0}, 150.0f);
    poses.emplace_back("elbow and knee at 150°", bent);
  }
  const char* step_text = std::getenv("SWEEPD_COLLISION_FRAME_STEP");
  const int step = step_text != nullptr ? std::max(1, std::atoi(step_text)) : 50;
  const io::BvhOptions cmu{.length_scale = 0.056444f};
  for (const char* clip : {"cmu_01_01.bvh", "cmu_01_03.bvh"}) {
    const motion::Retargeter retargeter(io::load_bvh(data / "motion" / clip, cmu), male);
    for (int frame = 0; frame < retargeter.frame_count(); frame += step)
      poses.emplace_back(std::string(clip) + " frame " + std::to_string(frame),
                         retargeter.pose_at_frame(frame));
  }

  using F = pb::Features;
  std::uint64_t sequence = 0;
  float largest = 0.0f;
  for (const auto& [what, pose] : poses) {
    SCOPED_TRACE(what);
    ++sequence;
    // Both daemons work at once: the comparison costs the slower one's time.
    ASSERT_TRUE(send_male_pose(gpu, pose, sequence, F::Folding | F::Protrusion | F::Contact));
    ASSERT_TRUE(send_male_pose(cpu, pose, sequence, F::Folding | F::Protrusion | F::Contact));
    const std::vector<float> on_gpu = receive_positions(gpu), on_cpu = receive_positions(cpu);
    ASSERT_EQ(on_gpu.size(), 3 * male.vertex_count()) << gpu.daemon.log();
    ASSERT_EQ(on_cpu.size(), on_gpu.size()) << cpu.daemon.log();
    // 1e-6 m, the issue's bound; the pairs are identical, so the vertices should be too.
    const float difference = largest_difference(on_gpu, on_cpu);
    EXPECT_LE(difference, 1e-6f);
    largest = std::max(largest, difference);
  }
  std::printf(
      "%zu poses of the male (clips every %d frames): largest GPU-CPU vertex difference "
      "%g m\n",
      poses.size(), step, largest);

  // The 150° pose is one where folding moves skin: the equality above compares features.
  ASSERT_TRUE(send_male_pose(cpu, poses[0].second, ++sequence, F::NONE));
  const std::vector<float> plain = receive_positions(cpu);
  ASSERT_TRUE(send_male_pose(cpu, poses[0].second, ++sequence, F::Folding | F::Protrusion));
  EXPECT_GT(largest_difference(plain, receive_positions(cpu)), 1e-3f)
      << "folding and protrusion at 150° should move skin by millimetres";
  // And contact moves skin of its own: cmu_01_03 frame 50 (standing, the arms down against the
  // torso), where contact moves the male's skin most among every 50th frame once folding and
  // protrusion have run (21 mm; at 4250, the most whole-body pairs, bench/collision_bench.cpp,
  // folding resolves them all).
  const deform::Pose crossing =
      motion::Retargeter(io::load_bvh(data / "motion" / "cmu_01_03.bvh", cmu), male)
          .pose_at_frame(50);
  ASSERT_TRUE(send_male_pose(cpu, crossing, ++sequence, F::Folding | F::Protrusion));
  const std::vector<float> without_contact = receive_positions(cpu);
  ASSERT_TRUE(send_male_pose(cpu, crossing, ++sequence, F::Folding | F::Protrusion | F::Contact));
  EXPECT_GT(largest_difference(without_contact, receive_positions(cpu)), 1e-3f)
      << "contact at cmu_01_03 frame 50 should move skin by millimetres";

  const pb::Stats* stats = request_stats(*gpu.client);
  ASSERT_NE(stats, nullptr);
  ASSERT_NE(stats->collision(), nullptr);
  const pb::CollisionStats& on_gpu = *stats->collision();
  EXPECT_EQ(on_gpu.backend()->str(), "gpu");
  EXPECT_NE(on_gpu.reason()->str().find("llvmpipe (software)"), std::string::npos)
      << on_gpu.reason()->str() << " (this test expects Mesa's llvmpipe; on a GPU say which)";
  EXPECT_FALSE(on_gpu.device()->str().empty());
  EXPECT_EQ(on_gpu.requests(), poses.size());
  EXPECT_EQ(on_gpu.gpu_fallbacks(), 0u);
  // Every pose detects at least once per region; each GPU detection uploads and reads back.
  EXPECT_GT(on_gpu.detect_ns(), 0u);
  EXPECT_GT(on_gpu.upload_ns(), 0u);
  EXPECT_GT(on_gpu.readback_ns(), 0u);
  EXPECT_GE(on_gpu.detect_ns(), on_gpu.upload_ns() + on_gpu.readback_ns());
  EXPECT_GT(on_gpu.fold_ns(), 0u);
  EXPECT_GT(on_gpu.protrude_ns(), 0u);
  EXPECT_GT(on_gpu.contact_ns(), 0u) << "cmu_01_03 frame 50 has whole-body contact";
  EXPECT_GT(on_gpu.dispatch_ns(), 0u);
  EXPECT_LE(on_gpu.dispatch_ns(), on_gpu.readback_ns()) << "dispatch is part of readback";
  std::printf(
      "gpu backend, %llu poses: detect %.1f ms (upload %.1f, readback %.1f), fold %.1f, "
      "protrude %.1f ms per pose\n",
      static_cast<unsigned long long>(on_gpu.requests()),
      on_gpu.detect_ns() * 1e-6 / on_gpu.requests(), on_gpu.upload_ns() * 1e-6 / on_gpu.requests(),
      on_gpu.readback_ns() * 1e-6 / on_gpu.requests(), on_gpu.fold_ns() * 1e-6 / on_gpu.requests(),
      on_gpu.protrude_ns() * 1e-6 / on_gpu.requests());

  // A connection's CPU work does not wait behind another's GPU wait: with one deformation
  // worker (--worker-threads 1), a plain pose on a second connection is answered while the
  // first connection's pose waits for its folding pairs on the GPU thread (about a second on
  // llvmpipe, against milliseconds for the plain pose). Were the GPU wait holding the worker,
  // the plain pose would be answered only after the folding one, at about the same time (the
  // replies are read in that order: the folding one's time is at least the plain one's).
  FrameClient second(gpu.daemon.port());
  ASSERT_NE(second.hello(""), nullptr);
  MaleDaemon& first = gpu;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point folding_sent = Clock::now();
  ASSERT_TRUE(send_male_pose(first, poses[0].second, ++sequence, F::Folding | F::Protrusion));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the first is under way
  const Clock::time_point plain_sent = Clock::now();
  {
    const std::vector<pb::Quat> wire = to_wire(poses[0].second.local_rotations);
    ASSERT_TRUE(send_pose(second, pose_fields(gpu.model_id, 1, wire)));
    ASSERT_NE(second.receive_as<pb::PosedVertices>(), nullptr);
  }
  const double plain_ms =
      std::chrono::duration<double, std::milli>(Clock::now() - plain_sent).count();
  ASSERT_EQ(receive_positions(first).size(), 3 * male.vertex_count());
  const double folding_ms =
      std::chrono::duration<double, std::milli>(Clock::now() - folding_sent).count();
  std::printf(
      "plain pose beside a GPU-folding one: answered in %.0f ms, the folding one in %.0f ms\n",
      plain_ms, folding_ms);
  // Half: room for a loaded machine; with the wait holding the worker the two were 1005 and
  // 1057 ms here. Only where the GPU wait is long enough to tell (llvmpipe; a GPU is fast).
  if (folding_ms > 200.0) {
    EXPECT_LT(plain_ms, 0.5 * folding_ms)
        << "the plain pose waited for the other connection's GPU folding";
  }

  stats = request_stats(*cpu.client);
  ASSERT_NE(stats, nullptr);
  ASSERT_NE(stats->collision(), nullptr);
  const pb::CollisionStats& on_cpu = *stats->collision();
  EXPECT_EQ(on_cpu.backend()->str(), "cpu");
  EXPECT_EQ(on_cpu.requests(), poses.size() + 3);  // the plain pose ran no features
  EXPECT_GT(on_cpu.detect_ns(), 0u);
  EXPECT_EQ(on_cpu.upload_ns(), 0u);  // nothing goes to a GPU
  EXPECT_EQ(on_cpu.readback_ns(), 0u);
  EXPECT_EQ(on_cpu.dispatch_ns(), 0u);
  EXPECT_GT(on_cpu.contact_ns(), 0u) << "cmu_01_03 frame 50 has whole-body contact";
  std::printf("cpu backend, %llu poses: detect %.1f ms, fold %.1f, protrude %.1f ms per pose\n",
              static_cast<unsigned long long>(on_cpu.requests()),
              on_cpu.detect_ns() * 1e-6 / on_cpu.requests(),
              on_cpu.fold_ns() * 1e-6 / on_cpu.requests(),
              on_cpu.protrude_ns() * 1e-6 / on_cpu.requests());
}

TEST(DaemonCollisionBackend, GpuWithoutEglIsAStartUpErrorNamingTheProblem) {
  const fs::path directory = fresh_directory("collision_no_egl");
  const fs::path log = directory / "sweepd.log";
  const std::string command = std::string(kNoEglVendor) + " " + SWEEPD_DAEMON +
                              " --collision gpu --port 0 --store-dir " +
                              (directory / "store").string() + " 2> " + log.string();
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), 2) << read_text(log);  // a configuration error
  const std::string text = read_text(log);
  EXPECT_NE(text.find("--collision gpu: no usable EGL context"), std::string::npos) << text;
  EXPECT_NE(text.find("needs an EGL driver"), std::string::npos) << text;
  // Refused before any work: no store was made, no model bound.
  EXPECT_FALSE(fs::exists(directory / "store"));
  fs::remove_all(directory);
}

TEST(DaemonCollisionBackend, AutoWithoutEglServesFoldingOnTheCpuAndSaysWhy) {
  const fs::path directory = fresh_directory("collision_auto_no_egl");
  std::unique_ptr<DaemonProcess> daemon;
  {
    const WithoutEglDriver no_egl;
    daemon = std::make_unique<DaemonProcess>(
        directory, std::vector<std::string>{"--collision", "auto", "--mannequin-vertices", "3000"});
  }
  ASSERT_TRUE(daemon->running()) << daemon->log();
  const std::string log = daemon->log();
  EXPECT_NE(log.find(R"("backend":"cpu","choice":"auto")"), std::string::npos) << log;
  EXPECT_NE(log.find("--collision auto: no usable EGL context"), std::string::npos) << log;

  FrameClient client(daemon->port());
  ASSERT_NE(client.hello(""), nullptr);
  // The mannequin's joint count, from ListModels.
  flatbuffers::FlatBufferBuilder builder;
  client.send_bytes(pb::finish_message(builder, pb::CreateListModels(builder), 3));
  const pb::ModelList* list = client.receive_as<pb::ModelList>();
  ASSERT_NE(list, nullptr);
  ASSERT_GT(list->models()->size(), 0u);
  const std::uint32_t joints = list->models()->Get(0)->joint_count();
  const std::vector<pb::Quat> rotations = to_wire(bent_rotations(joints));
  pb::PoseFields fields = pose_fields(list->models()->Get(0)->model_id(), 1, rotations);
  fields.features = pb::Features::Folding | pb::Features::Protrusion;
  ASSERT_TRUE(send_pose(client, fields));
  ASSERT_NE(client.receive_as<pb::PosedVertices>(), nullptr) << daemon->log();
  const pb::Stats* stats = request_stats(client);
  ASSERT_NE(stats, nullptr);
  ASSERT_NE(stats->collision(), nullptr);
  EXPECT_EQ(stats->collision()->backend()->str(), "cpu");
  EXPECT_EQ(stats->collision()->requests(), 1u);
  EXPECT_EQ(stats->collision()->gpu_fallbacks(), 0u);
  EXPECT_NE(stats->collision()->reason()->str().find("no usable EGL context"), std::string::npos);
  daemon.reset();
  fs::remove_all(directory);
}

}  // namespace
}  // namespace sweepd::test
