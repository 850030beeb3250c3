// ClipFile: the clip a client example (stream_poses, render_frames) sends to sweepd, from its
// command line: a BVH file, or an animation of a glTF file (protocol 1.7) or of an FBX or COLLADA
// file (1.8), retargeted by the server onto the model either way; or (1.13) no file: the model's
// range of motion, built by the server.
//   add_clip_file_flags(app, clip)  --bvh FILE [--bvh-scale S] (metres per clip unit; CMU:
//                     0.056444, the default) or --clip-from FILE [--clip NAME|INDEX] (the
//                     animation; default the first) or --range-of-motion; exactly one of the
//                     three (a usage error otherwise, naming them: checked in the app's final
//                     callback, which it sets)
//   file()            the file given, for messages and output names ("range_of_motion" for
//                     the range of motion)
//   read()            the file's contents, read once (throws naming the file); nothing for the
//                     range of motion
//   frame_count()     the clip's frames as the server counts them (io::parse_bvh,
//                     io::load_model_clip: the same readers), after read(); throws naming the
//                     file and the problem. None for the range of motion: its frames depend on
//                     the model's rig (1,441 for a full one), so only the server's ClipInfo says
//   upload_clip_file(connection, clip, model_id)  UploadClip of the contents read
//                     (client/clip_upload.h), with the model it will play on (1.12: its
//                     warnings then name what is left unmapped; the range of motion requires
//                     it): the server's ClipInfo, or its ServerError
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "client/connection.h"

namespace sweepd::client_examples {

struct ClipFile {
  std::string bvh;  // --bvh
  float bvh_scale = 0.056444f;
  std::string gltf;              // --clip-from
  std::string animation;         // --clip
  bool range_of_motion = false;  // --range-of-motion (protocol 1.13)
  std::vector<std::uint8_t> contents;

  const std::string& file() const;
  void read();
  std::optional<int> frame_count() const;
};

void add_clip_file_flags(CLI::App& app, ClipFile& clip);
const protocol::ClipInfo& upload_clip_file(client::Connection& connection, const ClipFile& clip,
                                           std::optional<std::uint32_t> model_id = std::nullopt);

}  // namespace sweepd::client_examples
