// ModelInfo's mesh ranges (protocol 1.6): a character of several meshes gives each mesh's name,
// material, vertex and triangle range, rigid joint and whether it is swept, so a client can
// split the vertex buffer; a model of one mesh gives one range over all of it.
#include <gtest/gtest.h>

#include <string>

#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"
#include "mannequin/mannequin.h"
#include "server/replies/model_info.h"
#include "tests/io/split_character.h"

namespace sweepd::test {
namespace {

namespace pb = sweepd::protocol;

// The ModelInfo the daemon would send for `model`, bound.
struct SentInfo {
  flatbuffers::FlatBufferBuilder builder;
  const pb::ModelInfo* info = nullptr;
};

void send_info(const deform::Model& model, SentInfo& sent) {
  server::RegisteredModel registered{
      .id = 7, .content_id = std::string(64, 'a'), .name = "body", .bound = {}, .bind_time_ns = 0};
  registered.bound = deform::bind(model, deform::detect_rig_map(model.skeleton));
  server::build_model_info(sent.builder, registered, 1);
  sent.info = pb::GetSizePrefixedMessage(sent.builder.GetBufferPointer())->body_as_ModelInfo();
}

TEST(ModelInfoMeshes, ACharacterOfSeveralMeshesGivesEachMeshsRange) {
  const deform::Model original = mannequin::make_mannequin({.target_vertices = 3000});
  const deform::Model model = io::testing::split_character(original).model;
  SentInfo sent;
  send_info(model, sent);
  ASSERT_NE(sent.info->meshes(), nullptr);
  ASSERT_EQ(sent.info->meshes()->size(), model.parts.size());
  std::uint32_t next = 0;
  for (std::size_t k = 0; k < model.parts.size(); ++k) {
    const pb::MeshRange& range = *sent.info->meshes()->Get(k);
    const deform::MeshPart& part = model.parts[k];
    EXPECT_EQ(range.name()->str(), part.name);
    EXPECT_EQ(range.material()->str(), part.material);
    EXPECT_EQ(range.first_vertex(), next);
    EXPECT_EQ(range.vertex_count(), part.vertex_count);
    EXPECT_EQ(range.first_triangle(), part.first_index / 3);
    EXPECT_EQ(range.triangle_count(), part.index_count / 3);
    EXPECT_EQ(range.rigid_joint(), part.rigid_joint);
    EXPECT_EQ(range.swept(), part.rigid_joint < 0);  // the hat alone stays apart
    EXPECT_EQ(range.mesh(), part.mesh);
    next += range.vertex_count();
  }
  EXPECT_EQ(next, sent.info->vertex_count());
  EXPECT_EQ(sent.info->meshes()->Get(4)->rigid_joint(), model.skeleton.find("Head"));
}

TEST(ModelInfoMeshes, AModelOfOneMeshGivesOneRange) {
  const deform::Model model = mannequin::make_mannequin({.target_vertices = 1500});
  SentInfo sent;
  send_info(model, sent);
  ASSERT_NE(sent.info->meshes(), nullptr);
  ASSERT_EQ(sent.info->meshes()->size(), 1u);
  const pb::MeshRange& range = *sent.info->meshes()->Get(0);
  EXPECT_EQ(range.name()->str(), "") << "the model's name is a label, not its mesh's";
  EXPECT_EQ(range.first_vertex(), 0u);
  EXPECT_EQ(range.vertex_count(), model.vertex_count());
  EXPECT_EQ(range.triangle_count(), model.triangle_count());
  EXPECT_EQ(range.rigid_joint(), -1);
  EXPECT_TRUE(range.swept());
}

}  // namespace
}  // namespace sweepd::test
