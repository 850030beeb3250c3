// client::bind_warning_lines: the server's binding warnings (ModelInfo.bind_warnings, protocol
// 1.14) as a client prints them, one line per warning naming the model; a ModelInfo from a
// server before 1.14 (no such field) reads as none, so old servers stay usable.
#include "client/bind_warnings.h"

#include <gtest/gtest.h>

namespace sweepd::client {
namespace {

namespace pb = sweepd::protocol;

TEST(BindWarningLines, NameTheModelAndGiveEachWarningsText) {
  flatbuffers::FlatBufferBuilder builder;
  std::vector<flatbuffers::Offset<pb::BindWarning>> warnings{
      pb::CreateBindWarningDirect(builder, "left arm", 7, 5.03f, 3.58f, "LBS",
                                  "elbow flexion 150°", 0, "", "left arm: worse than skinning"),
      pb::CreateBindWarningDirect(builder, "neck", 7, 3.15f, 2.66f, "DQS", "arms forward and up",
                                  0, "", "neck: worse than skinning")};
  const auto name = builder.CreateString("male");
  const auto list = builder.CreateVector(warnings);
  pb::ModelInfoBuilder info(builder);  // after its strings and vectors: tables do not nest
  info.add_name(name);
  info.add_self_check_poses(48);
  info.add_bind_warnings(list);
  builder.Finish(info.Finish());
  EXPECT_EQ(bind_warning_lines(*flatbuffers::GetRoot<pb::ModelInfo>(builder.GetBufferPointer())),
            (std::vector<std::string>{"model 'male': left arm: worse than skinning",
                                      "model 'male': neck: worse than skinning"}));
}

TEST(BindWarningLines, AModelInfoWithoutTheFieldHasNone) {
  flatbuffers::FlatBufferBuilder builder;
  builder.Finish(pb::CreateModelInfoDirect(builder, 1, "old"));  // what a 1.13 server sends
  const pb::ModelInfo& info = *flatbuffers::GetRoot<pb::ModelInfo>(builder.GetBufferPointer());
  EXPECT_EQ(info.self_check_poses(), 0u);
  EXPECT_TRUE(bind_warning_lines(info).empty());
}

}  // namespace
}  // namespace sweepd::client
