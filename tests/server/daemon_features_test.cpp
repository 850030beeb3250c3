// sweepd applying anatomical features (Pose.features): the vertices and normals it returns
// equal the library's own DeformJob output for the same selection bit for bit,
// a connection switches features per pose, ServerTimings.features_ns is filled, and features
// on LBS/DQS are refused with InvalidArgument.
#include <gtest/gtest.h>

#include <cstring>

#include "deform/job/anatomical_features.h"
#include "io/sweepbind/sweepbind.h"
#include "tests/server/daemon_process.h"
#include "tests/server/pose_frames.h"
#include "tests/server/stored_binding.h"

namespace sweepd::test {
namespace {

// One daemon for this program (killed at exit), and the mannequin exactly as it holds it:
// its stored binding, read back.
struct Served {
  fs::path directory = fresh_directory("features");
  DaemonProcess daemon{directory, {"--position-maps", "0"}};
  deform::BoundModel mannequin =
      io::load_sweepbind(stored_binding(directory / "store", "mannequin"));
  ~Served() { fs::remove_all(directory); }
};

const Served& served() {
  static const Served instance;
  return instance;
}

// Both elbows and knees bent hard (the skin there runs into itself), the rest slightly.
std::vector<glm::quat> hard_bend(const deform::Skeleton& skeleton) {
  std::vector<glm::quat> rotations = bent_rotations(skeleton.joints.size());
  for (const char* joint : {"LeftForeArm", "RightForeArm"})
    rotations[skeleton.find(joint)] = glm::angleAxis(glm::radians(140.0f), glm::vec3(0, 1, 0));
  for (const char* joint : {"LeftLeg", "RightLeg"})
    rotations[skeleton.find(joint)] = glm::angleAxis(glm::radians(140.0f), glm::vec3(1, 0, 0));
  return rotations;
}

void expect_bitwise_equal(const flatbuffers::Vector<float>* served,
                          const std::vector<glm::vec3>& library, const std::string& what) {
  ASSERT_NE(served, nullptr) << what;
  ASSERT_EQ(served->size(), 3 * library.size()) << what;
  EXPECT_EQ(std::memcmp(served->data(), library.data(), served->size() * sizeof(float)), 0)
      << what << " differ from the library's DeformJob output";
}

TEST(DaemonFeatures, RepliesEqualTheLibrarysFeaturesBitForBitAndSwitchPerPose) {
  ASSERT_TRUE(served().daemon.running()) << served().daemon.log();
  const deform::BoundModel& bound = served().mannequin;
  const std::vector<glm::quat> rotations = hard_bend(bound.model.skeleton);
  const std::vector<protocol::Quat> wire = to_wire(rotations);
  FrameClient client(served().daemon.port());
  ASSERT_NE(client.hello(""), nullptr);

  using F = protocol::Features;
  const deform::AnatomicalFeatures all{true, true, true, true}, none{};
  // All four, then none (the connection's deformer must drop volume and bulge again), then
  // folding and protrusion alone, then with whole-body contact (protocol 1.8).
  const std::pair<F, deform::AnatomicalFeatures> requests[] = {
      {F::Folding | F::Protrusion | F::Volume | F::Bulge, all},
      {F::NONE, none},
      {F::Folding | F::Protrusion, {true, true, false, false}},
      {F::Folding | F::Protrusion | F::Contact,
       {.folding = true, .protrusion = true, .contact = true}}};
  std::uint64_t sequence = 0;
  for (const auto& [bits, features] : requests) {
    const std::string what = "features '" + deform::to_string(features) + "'";
    SCOPED_TRACE(what);
    protocol::PoseFields fields = pose_fields(served().daemon.model_id(), ++sequence, wire);
    fields.features = bits;
    fields.normals = true;
    ASSERT_TRUE(send_pose(client, fields));
    const protocol::PosedVertices* reply = client.receive_as<protocol::PosedVertices>();
    ASSERT_NE(reply, nullptr);
    EXPECT_EQ(reply->sequence(), sequence);
    const Deformed library =
        library_deformation(bound, rotations, deform::DeformMethod::kSweep, features);
    const deform::FeatureReport& report = library.features;
    expect_bitwise_equal(reply->positions_f32(), library.positions, what + " positions");
    expect_bitwise_equal(reply->normals_f32(), library.normals, what + " normals");
    if (features.folding) {
      std::printf("mannequin bent 140°: %d pairs -> %d, %d folded, %d protruded\n",
                  report.pairs_before, report.pairs_after, report.folded, report.protruded);
      if (features.contact) {
        std::printf("  contact: %d whole-body pairs -> %d\n", report.contact_pairs_before,
                    report.contact_pairs_after);
        EXPECT_LT(report.contact_pairs_after, report.contact_pairs_before);
      }
      // Folding and protrusion take measurable time; without them nothing is spent.
      EXPECT_GT(reply->timings()->features_ns(), 0u);
    } else {
      EXPECT_EQ(reply->timings()->features_ns(), 0u);
    }
  }
  // The features changed the mesh, so the equalities above compare something.
  const Deformed plain = library_deformation(bound, rotations, deform::DeformMethod::kSweep);
  const Deformed featured =
      library_deformation(bound, rotations, deform::DeformMethod::kSweep, all);
  EXPECT_NE(plain.positions, featured.positions);
}

TEST(DaemonFeatures, FeaturesOnSkinningBaselinesAreAnInvalidArgument) {
  ASSERT_TRUE(served().daemon.running()) << served().daemon.log();
  const deform::BoundModel& bound = served().mannequin;
  const std::vector<protocol::Quat> wire =
      to_wire(bent_rotations(bound.model.skeleton.joints.size()));
  FrameClient client(served().daemon.port());
  ASSERT_NE(client.hello(""), nullptr);
  protocol::PoseFields fields = pose_fields(served().daemon.model_id(), 7, wire);
  fields.method = protocol::DeformMethod::Lbs;
  fields.features = protocol::Features::Volume;
  ASSERT_TRUE(send_pose(client, fields));
  const protocol::Error* error = client.receive_as<protocol::Error>();
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->code(), protocol::ErrorCode::InvalidArgument);
  EXPECT_EQ(error->sequence(), 7u);
  EXPECT_FALSE(error->fatal());
  EXPECT_NE(error->message()->str().find("sweep method only"), std::string::npos)
      << error->message()->str();
  // The connection is still served.
  fields.method = protocol::DeformMethod::Sweep;
  fields.sequence = 8;
  ASSERT_TRUE(send_pose(client, fields));
  const protocol::PosedVertices* reply = client.receive_as<protocol::PosedVertices>();
  ASSERT_NE(reply, nullptr);
  EXPECT_EQ(reply->sequence(), 8u);
}

}  // namespace
}  // namespace sweepd::test
