// sweepctl pose: a model deformed into a pose (a clip frame, a pose file), written as .glb —
// one frame, or a range of frames into a folder. With --server the daemon deforms.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli/commands.h"
#include "cli/posed_model.h"
#include "cli/remote_posed_model.h"
#include "console/progress_bar.h"
#include "io/gltf_save.h"

namespace sweepd::cli {

namespace {
// Writes the posed frames of `posed` (a PosedModel or a RemotePosedModel) as the command's
// output: one .glb, or frame_NNNNN.glb files in a folder for a frame range.
template <typename Posed>
void write_frames(Posed& posed, const std::filesystem::path& out) {
  const PosingArguments& posing = posed.arguments();
  deform::Model frame_model = posed.model();
  auto write_frame = [&](int frame, const std::filesystem::path& file) {
    posed.deform(frame, frame_model.positions, frame_model.normals);
    io::save_gltf(frame_model, file);
  };
  if (!posing.frame_range) {
    write_frame(posing.frames.first, out);
    if (posing.time)
      std::printf("wrote %s (%s, %g s)\n", out.string().c_str(), deform::to_string(posing.method),
                  *posing.time);
    else
      std::printf("wrote %s (%s, frame %d)\n", out.string().c_str(),
                  deform::to_string(posing.method), posing.frames.first);
    return;
  }
  std::filesystem::create_directories(out);
  {
    console::ProgressBar bar("posing " + posing.clip_file().filename().string());
    const int count = posing.frames.count();
    for (int frame = posing.frames.first; frame <= posing.frames.last; ++frame) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%05d.glb", frame);
      write_frame(frame, out / name);
      bar.update(static_cast<double>(frame - posing.frames.first + 1) / count, "writing frames");
    }
  }
  std::printf("wrote %d frames to %s (%s)\n", posing.frames.count(), out.string().c_str(),
              deform::to_string(posing.method));
}

struct Options {
  PosingArguments posing;
  std::filesystem::path out;
};

int pose(const Options& options, const ServerAddress& server) {
  const PosingArguments& posing = options.posing;
  const std::filesystem::path& out = options.out;
  if (!server.address.empty()) {
    RemotePosedModel posed(posing, server);
    std::printf("%s\n", posed.served_as().c_str());
    write_frames(posed, out);
    if (posing.features.collision()) {
      if (const std::string collision = posed.collision_summary(); !collision.empty())
        std::printf("%s\n", collision.c_str());
    }
    return 0;
  }
  PosedModel posed(posing);
  write_frames(posed, out);
  if (!posing.frame_range && posing.features.collision()) {
    const deform::FeatureReport& r = posed.feature_report();
    std::printf(
        "features: %d intersecting pairs before folding, %d after; %d vertices folded, "
        "%d pushed out of bone proxies; volume change %.1f cm3\n",
        r.pairs_before, r.pairs_after, r.folded, r.protruded, r.volume_change * 1e6);
    if (posing.features.contact)
      std::printf("contact: %d whole-body pairs before, %d after; %d vertices pulled back\n",
                  r.contact_pairs_before, r.contact_pairs_after, r.contact_moved);
  }
  if (const LocalCollision* collision = posed.collision())
    std::printf("%s\n", collision->summary().c_str());
  return 0;
}

}  // namespace

Command add_pose_command(CLI::App& sweepctl, const ServerAddress& server) {
  CLI::App* command =
      sweepctl.add_subcommand("pose", "deform a model into a pose or clip frames, write .glb");
  command->footer(
      "With --server the daemon deforms: MODEL is then a local .glb/.gltf (uploaded) or a\n"
      "model name on the server.");
  auto options = std::make_shared<Options>();
  add_posing_flags(*command, options->posing, ClipFrames::kOneOrRange);
  add_method_flags(*command, options->posing);
  command
      ->add_option("-o", options->out,
                   "posed .glb for one frame; a folder for --frames (frame_NNNNN.glb)")
      ->type_name("OUT")
      ->required();
  command->callback(
      [options, &server] { check_method_flags(options->posing, !server.address.empty()); });
  return {command, [options, &server] { return pose(*options, server); }, true};
}

}  // namespace sweepd::cli
