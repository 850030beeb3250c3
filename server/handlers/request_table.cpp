#include "server/handlers/request_table.h"

#include "server/handlers/bye_handler.h"
#include "server/handlers/contact_sheet_request_handler.h"
#include "server/handlers/edit_key_ellipse_handler.h"
#include "server/handlers/hello_handler.h"
#include "server/handlers/list_models_handler.h"
#include "server/handlers/load_model_handler.h"
#include "server/handlers/map_shared_memory_handler.h"
#include "server/handlers/mesh_request_handler.h"
#include "server/handlers/pose_by_name_handler.h"
#include "server/handlers/pose_from_clip_handler.h"
#include "server/handlers/pose_handler.h"
#include "server/handlers/position_map_request_handler.h"
#include "server/handlers/stats_request_handler.h"
#include "server/handlers/subscribe_stream_handler.h"
#include "server/handlers/upload_clip_handler.h"

namespace sweepd::server {
namespace {

namespace pb = sweepd::protocol;

struct Registration {
  pb::Body type;
  RequestHandler handler;
};

// Poses first: they are most of the traffic.
constexpr Registration kRequests[] = {
    {pb::Body::Pose, handle_pose},
    {pb::Body::PoseFromClip, handle_pose_from_clip},
    {pb::Body::PoseByName, handle_pose_by_name},
    {pb::Body::PositionMapRequest, handle_position_map_request},
    {pb::Body::ListModels, handle_list_models},
    {pb::Body::LoadModel, handle_load_model},
    {pb::Body::MeshRequest, handle_mesh_request},
    {pb::Body::EditKeyEllipse, handle_edit_key_ellipse},
    {pb::Body::UploadClip, handle_upload_clip},
    {pb::Body::ContactSheetRequest, handle_contact_sheet_request},
    {pb::Body::MapSharedMemory, handle_map_shared_memory},
    {pb::Body::SubscribeStream, handle_subscribe_stream},
    {pb::Body::StatsRequest, handle_stats_request},
    {pb::Body::Hello, handle_hello},
    {pb::Body::Bye, handle_bye},
};

}  // namespace

RequestHandler handler_for(pb::Body type) {
  for (const Registration& registration : kRequests)
    if (registration.type == type) return registration.handler;
  return nullptr;
}

}  // namespace sweepd::server
