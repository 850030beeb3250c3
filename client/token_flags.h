// add_token_flags: how every C++ client takes sweepd's auth token (sweepctl --server,
// stream_poses, render_frames), into `token`:
//   --token T            the token itself (visible in the process list)
//   --token-file FILE    the first line of FILE, as sweepd's own --token-file reads it (a
//                        Kubernetes Secret or systemd credential mounted as a file); a file
//                        that cannot be read is a usage error naming it
// The two exclude each other. `needs` (optional): an option they need, e.g. sweepctl's
// --server.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace sweepd::client {

void add_token_flags(CLI::App& app, std::string& token, CLI::Option* needs = nullptr);

}  // namespace sweepd::client
