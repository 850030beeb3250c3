// The served model's binding warnings (ModelInfo.bind_warnings, protocol 1.14): each body region
// where the server's self-check found the sweep still worse than skinning on the model's range
// of motion (issue 47), as `sweepctl bind` prints them locally.
//
// bind_warning_lines(info): "model 'NAME': TEXT" per warning; empty when there is none, or
//   from a server before 1.14 (which sends no field).
// print_bind_warnings(out, info): each line as "warning: ...", what sweepctl --server,
//   stream_poses and render_frames print once they hold the model. Read `info` before the
//   connection's next receive (it points into the receive buffer).
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "protocol/sweepd_generated.h"

namespace sweepd::client {

std::vector<std::string> bind_warning_lines(const protocol::ModelInfo& info);
void print_bind_warnings(std::FILE* out, const protocol::ModelInfo& info);

}  // namespace sweepd::client
