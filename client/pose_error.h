// pose_error_cause: what a pose's Error says, for a client that names the frame itself —
// "server error InvalidArgument: clip 'walk' on model 3: frame 1441 is past ...", without the
// "pose S: " the server puts first when S is the Error's own sequence (a client's numbering:
// render_frames and stream_poses send frame F as sequence F + 1), so that one cause of many
// frames reads alike (console/frame_failures.h).
#pragma once

#include <string>

#include "protocol/messages.h"

namespace sweepd::client {

std::string pose_error_cause(const protocol::Error& error);

}  // namespace sweepd::client
