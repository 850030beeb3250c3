#include "client_examples/clip_file_flags.h"

#include <filesystem>
#include <stdexcept>
#include <string_view>

#include "client/clip_upload.h"
#include "io/bvh/bvh_load.h"
#include "io/files/file_bytes.h"
#include "io/model_clip_load.h"

namespace sweepd::client_examples {

void add_clip_file_flags(CLI::App& app, ClipFile& clip) {
  CLI::Option* bvh = app.add_option("--bvh", clip.bvh, "a BVH clip")->type_name("FILE");
  CLI::Option* gltf =
      app.add_option("--clip-from", clip.gltf,
                     "a glTF (protocol 1.7), FBX or COLLADA (1.8) file whose animation (--clip) "
                     "is the clip")
          ->type_name("FILE")
          ->excludes(bvh);
  app.add_option("--bvh-scale", clip.bvh_scale, "metres per BVH unit (CMU: 0.056444)")
      ->capture_default_str()
      ->needs(bvh);
  app.add_option("--clip", clip.animation,
                 "the animation of --clip-from: its name or index (default: the first)")
      ->type_name("NAME|INDEX")
      ->needs(gltf);
  app.add_flag("--range-of-motion", clip.range_of_motion,
               "no clip file: the model's range of motion, built by the server (protocol 1.13; "
               "`sweepctl rom` writes the same clip)")
      ->excludes(bvh)
      ->excludes(gltf);
  // The app's own callback (these examples have none): one of the three is required.
  app.final_callback([&clip] {
    if (clip.file().empty()) throw CLI::RequiredError("--bvh, --clip-from or --range-of-motion");
  });
}

const std::string& ClipFile::file() const {
  static const std::string range_of_motion_name = "range_of_motion";
  if (range_of_motion) return range_of_motion_name;
  return bvh.empty() ? gltf : bvh;
}

void ClipFile::read() {
  if (!range_of_motion) contents = io::read_file_bytes(file());
}

std::optional<int> ClipFile::frame_count() const {
  if (range_of_motion) return std::nullopt;
  if (!gltf.empty())
    return io::load_model_clip(contents, std::filesystem::path(gltf).filename(),
                               animation.empty() ? "0" : animation)
        .frame_count;
  const std::string_view text(reinterpret_cast<const char*>(contents.data()), contents.size());
  return io::parse_bvh(text, bvh, {.length_scale = bvh_scale}).frame_count;
}

const protocol::ClipInfo& upload_clip_file(client::Connection& connection, const ClipFile& clip,
                                           std::optional<std::uint32_t> model_id) {
  if (clip.range_of_motion) {
    if (!model_id) throw std::invalid_argument("the range of motion needs the model's id");
    return client::upload_range_of_motion(connection, *model_id);
  }
  const std::string name = std::filesystem::path(clip.file()).filename().string();
  if (!clip.gltf.empty())
    return client::upload_gltf_clip(connection, name, clip.contents, clip.animation, false, {},
                                    model_id);
  const std::string_view text(reinterpret_cast<const char*>(clip.contents.data()),
                              clip.contents.size());
  return client::upload_clip(connection, name, text, clip.bvh_scale, {}, model_id);
}

}  // namespace sweepd::client_examples
