// sweepctl pose: a model deformed into a pose (a clip frame, a pose file), written as .glb —
// one frame, or a range of frames into a folder — or clip frames as a PC2 or MDD point cache
// (io/point_cache/point_cache_save.h), streamed frame by frame. With --server the daemon deforms.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "cli/commands.h"
#include "cli/posed_model.h"
#include "cli/remote_posed_model.h"
#include "console/command_line.h"
#include "console/progress_bar.h"
#include "io/gltf/gltf_save.h"
#include "io/point_cache/point_cache_save.h"

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

// A frame's positions for a cache: deformed here without normals, or the server's (which come
// with their normals).
void cache_frame(PosedModel& posed, int frame, std::vector<glm::vec3>& positions,
                 std::vector<glm::vec3>&) {
  posed.deform_positions(frame, positions);
}
void cache_frame(RemotePosedModel& posed, int frame, std::vector<glm::vec3>& positions,
                 std::vector<glm::vec3>& normals) {
  posed.deform(frame, positions, normals);
}

// Writes the clip frames of `posed` as the point cache `out`, one frame deformed and written at a
// time (memory: one frame), with a progress bar on stderr.
template <typename Posed>
void write_point_cache(Posed& posed, const std::filesystem::path& out, io::PointCacheAxes axes) {
  const PosingArguments& posing = posed.arguments();
  const io::PointCacheFormat format = *io::point_cache_format(out);
  io::PointCacheWriter cache(
      out, {.format = format,
            .axes = axes,
            .point_count = static_cast<int>(posed.model().vertex_count()),
            .frame_count = posing.frames.count(),
            .first_frame = posing.frames.first,
            .frames_per_second = posing.fps > 0.0f ? posing.fps : posed.clip_frames_per_second()});
  std::vector<glm::vec3> positions, normals;
  {
    console::ProgressBar bar("caching " + posing.clip_file().filename().string());
    for (int frame = posing.frames.first; frame <= posing.frames.last; ++frame) {
      cache_frame(posed, frame, positions, normals);
      cache.write_frame(positions);
      bar.update(static_cast<double>(frame - posing.frames.first + 1) / posing.frames.count(),
                 "writing frames");
    }
  }
  cache.finish();
  std::printf("wrote %d frames of %zu vertices to %s (%s, %s axes, %s)\n", posing.frames.count(),
              positions.size(), out.string().c_str(),
              format == io::PointCacheFormat::kPc2 ? "PC2" : "MDD",
              axes == io::PointCacheAxes::kBlender ? "Blender's Z-up" : "glTF's Y-up",
              deform::to_string(posing.method));
}

struct PoseCommandOptions {
  PosingArguments posing;
  std::filesystem::path out;
  io::PointCacheAxes axes = io::PointCacheAxes::kGltf;
};

// Writes what -o names: a point cache, or .glb frames.
template <typename Posed>
void write_output(Posed& posed, const PoseCommandOptions& options) {
  if (io::point_cache_format(options.out))
    write_point_cache(posed, options.out, options.axes);
  else
    write_frames(posed, options.out);
}

// The rules between -o, --axes and the frames that CLI11 cannot state.
void check_output(const PoseCommandOptions& options, bool axes_given) {
  const PosingArguments& posing = options.posing;
  const bool cache = io::point_cache_format(options.out).has_value();
  if (axes_given && !cache)
    throw CLI::ValidationError("--axes applies to a point cache: -o FILE.pc2 or FILE.mdd, not '" +
                               options.out.string() + "'");
  if (cache && !posing.has_clip())
    throw CLI::ValidationError("-o " + options.out.string() +
                               ": a point cache holds clip frames: give --bvh, --clip or "
                               "--clip-from, and --frames A-B");
  if (cache && posing.time)
    throw CLI::ValidationError("-o " + options.out.string() +
                               ": a point cache holds whole clip frames (--frame N or --frames "
                               "A-B), not a time (--time)");
  if (posing.frame_range && !cache && options.out.has_extension())
    throw CLI::ValidationError(
        "-o " + options.out.string() +
        ": --frames writes a folder of .glb frames (a name "
        "without an extension) or a point cache (FILE.pc2 or FILE.mdd), not a '" +
        options.out.extension().string() + "' file");
}

int pose(const PoseCommandOptions& options, const ServerAddress& server) {
  const PosingArguments& posing = options.posing;
  if (!server.address.empty()) {
    RemotePosedModel posed(posing, server);
    std::printf("%s\n", posed.served_as().c_str());
    write_output(posed, options);
    if (posing.features.collision()) {
      if (const std::string collision = posed.collision_summary(); !collision.empty())
        std::printf("%s\n", collision.c_str());
    }
    return 0;
  }
  PosedModel posed(posing);
  write_output(posed, options);
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
      "With --server the daemon deforms: MODEL is then a local .glb/.gltf/.fbx/.dae (uploaded)\n"
      "or a model name on the server.");
  auto options = std::make_shared<PoseCommandOptions>();
  add_posing_flags(*command, options->posing, ClipFrames::kOneOrRange);
  add_method_flags(*command, options->posing);
  command
      ->add_option("-o", options->out,
                   "posed .glb for one frame; a folder for --frames (frame_NNNNN.glb); or a "
                   "point cache of the frames, FILE.pc2 (PC2) or FILE.mdd (MDD)")
      ->type_name("OUT")
      ->required();
  CLI::Option* axes = console::add_choice(*command, "--axes", options->axes,
                                          io::point_cache_axes_names(), io::kPointCacheAxesHelp);
  axes->type_name("gltf|blender");
  command->callback([options, axes, &server] {
    check_method_flags(options->posing, !server.address.empty());
    check_output(*options, axes->count() > 0);
  });
  return {command, [options, &server] { return pose(*options, server); }, true};
}

}  // namespace sweepd::cli
