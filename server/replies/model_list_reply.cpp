#include "server/replies/model_list_reply.h"

#include <vector>

#include "protocol/messages.h"

namespace sweepd::server {

void build_model_list(flatbuffers::FlatBufferBuilder& builder, std::span<const ModelHandle> models,
                      std::span<const std::string> directory_entries, std::uint64_t request_id) {
  namespace pb = sweepd::protocol;
  std::vector<flatbuffers::Offset<pb::ModelSummary>> summaries;
  for (const ModelHandle& model : models) {
    summaries.push_back(pb::CreateModelSummaryDirect(
        builder, model->id, model->name.c_str(),
        static_cast<std::uint32_t>(model->bound.model.vertex_count()),
        static_cast<std::uint32_t>(model->bound.model.skeleton.joints.size()),
        model->content_id.c_str()));
  }
  for (const std::string& name : directory_entries) {
    summaries.push_back(pb::CreateModelSummaryDirect(builder, 0, name.c_str(), 0, 0));
  }
  pb::finish_message(builder, pb::CreateModelListDirect(builder, &summaries), request_id);
}

}  // namespace sweepd::server
