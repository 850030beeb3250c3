// The request table (server/handlers/request_table.h): every message type of the schema is
// either a request with its handler or a reply with none, so a type added to the schema fails
// here until it is sorted; and the handlers that refuse a request from its message alone (a
// second Hello, a field missing, shared memory off a Unix socket) answer as the transport did
// before they were split out of it, through a session that records what they ask.
#include "server/handlers/request_table.h"

#include <gtest/gtest.h>

#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "protocol/messages.h"

namespace sweepd::server {
namespace {

namespace pb = sweepd::protocol;

const std::set<pb::Body> kRequests = {pb::Body::Hello,
                                      pb::Body::Bye,
                                      pb::Body::ListModels,
                                      pb::Body::LoadModel,
                                      pb::Body::Pose,
                                      pb::Body::PositionMapRequest,
                                      pb::Body::EditKeyEllipse,
                                      pb::Body::StatsRequest,
                                      pb::Body::MeshRequest,
                                      pb::Body::UploadClip,
                                      pb::Body::PoseFromClip,
                                      pb::Body::PoseByName,
                                      pb::Body::MapSharedMemory,
                                      pb::Body::ContactSheetRequest,
                                      pb::Body::SubscribeStream};
const std::set<pb::Body> kReplies = {
    pb::Body::NONE,          pb::Body::Welcome,     pb::Body::ModelList,    pb::Body::ModelInfo,
    pb::Body::PosedVertices, pb::Body::PositionMap, pb::Body::Stats,        pb::Body::Error,
    pb::Body::Mesh,          pb::Body::ClipInfo,    pb::Body::SharedMemory, pb::Body::ContactSheet,
    pb::Body::StreamSubscribed};

TEST(RequestTable, EveryRequestOfTheSchemaHasAHandlerAndNoReplyHasOne) {
  for (const pb::Body type : pb::EnumValuesBody()) {
    const std::string name = pb::EnumNameBody(type);
    ASSERT_TRUE(kRequests.contains(type) || kReplies.contains(type))
        << name << " is new in the schema: a request (register its handler in "
        << "server/handlers/request_table.cpp) or a reply? Add it to this test's lists";
    EXPECT_EQ(handler_for(type) != nullptr, kRequests.contains(type)) << name;
  }
  for (const pb::Body type : kRequests)
    EXPECT_FALSE(kReplies.contains(type)) << pb::EnumNameBody(type);
}

// What a handler asked of its connection. A handler tested here must not need the server's
// services: environment() throws.
class RecordingSession final : public RequestSession {
 public:
  struct Sent {
    pb::ErrorCode code;
    std::string message;
    std::uint64_t request_id;
  };

  std::uint64_t connection_id() const override { return 7; }
  ConnectionEnvironment& environment() override {
    throw std::logic_error("this handler reached for the server's services");
  }
  flatbuffers::FlatBufferBuilder take_builder() override {
    return flatbuffers::FlatBufferBuilder();
  }
  void send(flatbuffers::FlatBufferBuilder) override { ++replies; }
  void send_error(const RequestError& error, std::uint64_t request_id) override {
    errors.push_back({error.code, error.message, request_id});
  }
  void queue_pose(std::variant<PoseRequest, RequestError>, std::uint64_t) override { ++poses; }
  void run_in_order(Pool, std::function<Reply()>) override { ++off_thread; }
  void drain() override { drained = true; }
  pb::PoseDelivery delivery() const override { return pb::PoseDelivery::InOrder; }
  std::weak_ptr<RequestSession> weak_session() override { return {}; }
  bool draining() const override { return drained; }
  bool unix_socket() override { return on_unix_socket; }
  const SharedRegion* shared_region() const override { return region.get(); }
  void send_region(std::shared_ptr<const SharedRegion>, flatbuffers::FlatBufferBuilder) override {
    ++replies;
  }

  bool on_unix_socket = false;
  std::shared_ptr<const SharedRegion> region;
  std::vector<Sent> errors;
  int replies = 0, poses = 0, off_thread = 0;
  bool drained = false;
};

// `body` in a Message with request id 42, handed to its registered handler.
template <typename Body>
void handle(flatbuffers::FlatBufferBuilder& builder, flatbuffers::Offset<Body> body,
            RecordingSession& session) {
  pb::finish_message(builder, body, 42);
  const pb::Message* message =
      flatbuffers::GetSizePrefixedRoot<pb::Message>(builder.GetBufferPointer());
  const RequestHandler handler = handler_for(message->body_type());
  ASSERT_NE(handler, nullptr);
  handler(*message, session);
}

TEST(RequestTable, ASecondHelloIsRefusedAndTheSessionGoesOn) {
  RecordingSession session;
  flatbuffers::FlatBufferBuilder builder;
  handle(builder, pb::CreateHelloDirect(builder, pb::kProtocolVersionMajor, 0, "", "again"),
         session);
  ASSERT_EQ(session.errors.size(), 1u);
  EXPECT_EQ(session.errors[0].code, pb::ErrorCode::InvalidArgument);
  EXPECT_EQ(session.errors[0].message, "Hello was already received on this connection");
  EXPECT_EQ(session.errors[0].request_id, 42u);
  EXPECT_FALSE(session.drained);
}

TEST(RequestTable, ByeDrainsTheConnectionAndSendsNothing) {
  RecordingSession session;
  flatbuffers::FlatBufferBuilder builder;
  handle(builder, pb::CreateByeDirect(builder, "done"), session);
  EXPECT_TRUE(session.drained);
  EXPECT_TRUE(session.errors.empty());
  EXPECT_EQ(session.replies, 0);
}

TEST(RequestTable, PoseCarryingRequestsWithoutTheirPoseAreRefusedNamingWhatIsMissing) {
  RecordingSession session;
  flatbuffers::FlatBufferBuilder map, from_clip, by_name;
  handle(map, pb::CreatePositionMapRequest(map), session);
  handle(from_clip, pb::CreatePoseFromClip(from_clip), session);
  handle(by_name, pb::CreatePoseByName(by_name), session);
  ASSERT_EQ(session.errors.size(), 3u);
  EXPECT_EQ(session.errors[0].message, "a PositionMapRequest needs a pose");
  EXPECT_EQ(session.errors[1].message, "a PoseFromClip needs a pose and a clip");
  EXPECT_EQ(session.errors[2].message, "a PoseByName needs a pose");
  for (const RecordingSession::Sent& sent : session.errors) {
    EXPECT_EQ(sent.code, pb::ErrorCode::InvalidArgument);
    EXPECT_EQ(sent.request_id, 42u);
  }
  EXPECT_EQ(session.poses, 0);  // nothing reached the pose queue
}

TEST(RequestTable, SharedMemoryIsRefusedOffAUnixSocketAndASecondTimeOnOne) {
  RecordingSession tcp;
  flatbuffers::FlatBufferBuilder first;
  handle(first, pb::CreateMapSharedMemory(first, 4096), tcp);
  ASSERT_EQ(tcp.errors.size(), 1u);
  EXPECT_EQ(tcp.errors[0].code, pb::ErrorCode::NotAvailable);
  EXPECT_NE(tcp.errors[0].message.find("needs a Unix socket"), std::string::npos);

  RecordingSession unix_socket;
  unix_socket.on_unix_socket = true;
  unix_socket.region = SharedRegion::create(8192);
  flatbuffers::FlatBufferBuilder second;
  handle(second, pb::CreateMapSharedMemory(second, 4096), unix_socket);
  ASSERT_EQ(unix_socket.errors.size(), 1u);
  EXPECT_EQ(unix_socket.errors[0].code, pb::ErrorCode::InvalidArgument);
  EXPECT_EQ(unix_socket.errors[0].message,
            "this connection has a shared region already (8192 bytes); it maps one");
  EXPECT_EQ(unix_socket.replies, 0);
}

}  // namespace
}  // namespace sweepd::server
