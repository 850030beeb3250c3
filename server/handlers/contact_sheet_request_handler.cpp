#include "server/handlers/contact_sheet_request_handler.h"

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "server/elapsed_time.h"
#include "server/handlers/reply_size.h"
#include "server/handlers/work_size.h"
#include "server/log_event.h"
#include "server/replies/contact_sheet_reply.h"

namespace sweepd::server {
namespace {

namespace pb = sweepd::protocol;

// On the GPU waiters' pool: the sheet drawn, and the reply the I/O thread sends. The working
// memory stays reserved until the reply is built.
RequestSession::Reply draw_sheet(ConnectionEnvironment& environment,
                                 std::shared_ptr<const SheetWork> work,
                                 std::shared_ptr<const WorkReservation> reserved,
                                 std::uint64_t request_id) {
  const auto start = std::chrono::steady_clock::now();
  auto picture = std::make_shared<sheet::SheetPicture>();
  std::optional<RequestError> failure;
  try {
    CollisionPairFinder pairs(environment.collision);
    environment.contact_sheets.render(*work, &pairs, *picture);
  } catch (const std::exception& error) {
    failure = RequestError{error_code_of(error), error.what()};
  }
  const std::uint64_t took_ns = nanoseconds_since(start);
  return [work, picture, failure, took_ns, request_id, reserved](RequestSession& session) {
    if (failure) {
      log_event("contact_sheet_failed",
                {{"connection", session.connection_id()}, {"reason", failure->message}});
      session.send_error(*failure, request_id);
      return;
    }
    log_event("contact_sheet", {{"connection", session.connection_id()},
                                {"width", picture->width},
                                {"height", picture->height},
                                {"png_bytes", picture->png.size()},
                                {"ms", static_cast<double>(took_ns) / 1e6}});
    flatbuffers::FlatBufferBuilder builder = session.take_builder();
    build_contact_sheet(builder, work->model->id, *picture, request_id);
    session.send(std::move(builder));
  };
}

}  // namespace

void handle_contact_sheet_request(const pb::Message& message, RequestSession& session) {
  const std::uint64_t request_id = message.request_id();
  ConnectionEnvironment& environment = session.environment();
  // Checked and copied here: the request lives in the reader's storage.
  std::variant<SheetWork, RequestError> read = read_contact_sheet_request(
      environment.models, environment.clips, *message.body_as_ContactSheetRequest());
  if (const RequestError* error = std::get_if<RequestError>(&read)) {
    session.send_error(*error, request_id);
    return;
  }
  auto work = std::make_shared<const SheetWork>(std::move(std::get<SheetWork>(read)));
  if (auto error = check_sheet_fits(work->options, environment.config.max_frame_bytes)) {
    session.send_error(*error, request_id);
    return;
  }
  // The picture, its PNG and the renderer's targets are held while it is drawn: reserved from
  // the work budget every client shares.
  auto reserved =
      environment.work_budget.reserve(session.connection_id(), sheet_work_bytes(work->options));
  if (const WorkRefusal* refusal = std::get_if<WorkRefusal>(&reserved)) {
    session.send_error(work_refused("contact sheet", *refusal,
                                    "ask for smaller cells, fewer frames or fewer methods"),
                       request_id);
    return;
  }
  log_event("contact_sheet_start", {{"connection", session.connection_id()},
                                    {"model", work->model->id},
                                    {"frames", work->options.frames.size()},
                                    {"methods", work->options.methods.size()}});
  session.run_in_order(RequestSession::Pool::kGpuWaiters,
                       [environment = &environment, work,
                        reserved = std::get<std::shared_ptr<const WorkReservation>>(reserved),
                        request_id]() { return draw_sheet(*environment, work, reserved, request_id); });
}

}  // namespace sweepd::server
