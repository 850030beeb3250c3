#include "server/handlers/model_change.h"

#include <utility>

#include "server/replies/model_info.h"

namespace sweepd::server {

void answer_model_change(RequestSession& session, std::uint64_t request_id,
                         std::function<ModelChange()> change, LogModelChange log_outcome) {
  session.run_in_order(
      RequestSession::Pool::kWorkers,
      [change = std::move(change), log_outcome, request_id]() -> RequestSession::Reply {
        return [outcome = change(), log_outcome, request_id](RequestSession& session) {
          log_outcome(session.connection_id(), outcome);
          if (const ModelHandle* model = std::get_if<ModelHandle>(&outcome)) {
            flatbuffers::FlatBufferBuilder builder = session.take_builder();
            build_model_info(builder, **model, request_id);
            session.send(std::move(builder));
          } else {
            const RequestError& error = std::get<RequestError>(outcome);
            session.send_error({error.code, error.message}, request_id);
          }
        };
      });
}

}  // namespace sweepd::server
