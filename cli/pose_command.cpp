// sweepctl pose: a model deformed into a pose (a clip frame, a pose file), written as .glb —
// one frame, or a range of frames into a folder.
#include <cstdio>
#include <filesystem>

#include "cli/commands.h"
#include "cli/posed_model.h"
#include "cli/progress_bar.h"
#include "cli/subcommand.h"
#include "io/gltf_save.h"

namespace sweepd::cli {

namespace {
const std::string kUsage =
    std::string(
        "usage: sweepctl pose MODEL [--bvh CLIP [--frame N | --frames A-B]] [--pose POSE.json]\n"
        "                     [--method sweep|lbs|dqs] -o OUT\n"
        "  -o OUT             posed .glb for one frame; a folder for --frames "
        "(frame_NNNNN.glb)\n") +
    kPosingUsage;
}  // namespace

int run_pose(const std::vector<std::string>& arguments) {
  PosingArguments posing;
  std::filesystem::path out;
  auto parse = [&](std::vector<std::string> args) {
    std::string problem = take_posing_arguments(args, posing);
    if (!problem.empty()) return problem;
    if (args.size() == 2 && args[0] == "-o") {
      out = args[1];
      return std::string();
    }
    return args.empty() ? std::string("missing -o OUT") : "unexpected argument '" + args[0] + "'";
  };
  return run_subcommand("pose", kUsage, arguments, parse, [&] {
    PosedModel posed(posing);
    deform::Model frame_model = posed.model();
    auto write_frame = [&](int frame, const std::filesystem::path& file) {
      posed.deform(frame, frame_model.positions, frame_model.normals);
      io::save_gltf(frame_model, file);
    };
    if (!posing.frame_range) {
      write_frame(posing.first_frame, out);
      std::printf("wrote %s (%s, frame %d)\n", out.string().c_str(),
                  deform::to_string(posing.method), posing.first_frame);
      if (posing.features.collision()) {
        const deform::FeatureReport& r = posed.feature_report();
        std::printf(
            "features: %d intersecting pairs before folding, %d after; %d vertices folded, "
            "%d pushed out of bone proxies; volume change %.1f cm3\n",
            r.pairs_before, r.pairs_after, r.folded, r.protruded, r.volume_change * 1e6);
      }
      return 0;
    }
    std::filesystem::create_directories(out);
    {
      ProgressBar bar("posing " + posing.bvh.filename().string());
      const int count = posing.last_frame - posing.first_frame + 1;
      for (int frame = posing.first_frame; frame <= posing.last_frame; ++frame) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%05d.glb", frame);
        write_frame(frame, out / name);
        bar.update(static_cast<double>(frame - posing.first_frame + 1) / count, "writing frames");
      }
    }
    std::printf("wrote %d frames to %s (%s)\n", posing.last_frame - posing.first_frame + 1,
                out.string().c_str(), deform::to_string(posing.method));
    return 0;
  });
}

}  // namespace sweepd::cli
