// sweepctl rom MODEL -o rom.glb: the model's range of motion (motion/range_of_motion.h) written
// with the model as a glTF animation, for a DCC tool or any glTF viewer to play, and for
// `sweepctl check rom.glb --clip "range of motion"` or the daemon to pose.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli/commands.h"
#include "cli/model_loading.h"
#include "io/gltf/gltf_save.h"
#include "motion/range_of_motion.h"

namespace sweepd::cli {

namespace {

struct RomCommandOptions {
  std::filesystem::path model, rig, out;
  bool list = false;
};

int write_rom(const RomCommandOptions& options) {
  const LoadedModel loaded = load_model_and_rig(options.model, options.rig);
  const motion::RangeOfMotion rom = motion::range_of_motion(loaded.model.skeleton, loaded.rig);
  io::SaveOptions save;
  save.animations.push_back({motion::kRomClipName, rom.clip.tracks});
  io::save_gltf(loaded.model, options.out, save);
  std::printf("wrote %s: animation \"%s\", %zu moves, %d frames at %d fps (%.0f s)\n",
              options.out.string().c_str(), motion::kRomClipName, rom.moves.size(),
              rom.clip.frame_count, motion::kRomFramesPerSecond, rom.clip.duration());
  if (options.list)
    for (const motion::RomMove& move : rom.moves)
      std::printf("  frames %4d-%4d (peak %4d)  %s\n", move.first_frame,
                  move.first_frame + motion::kRomFramesPerMove, move.peak_frame,
                  move.name.c_str());
  return 0;
}

}  // namespace

Command add_rom_command(CLI::App& sweepctl) {
  CLI::App* command = sweepctl.add_subcommand(
      "rom", "write the model's range of motion as a glTF animation");
  command->footer(
      "Every joint of the rig map through its anatomical range, alone and combined (hips,\n"
      "knees, ankles, spine, neck, shoulders, clavicles, elbows, forearms, wrists; knee to\n"
      "chest, deep squat, kneeling, lunge, reaching, twisting), 1 s per move at 30 fps, written\n"
      "with the model as one .glb. `sweepctl check MODEL` measures the same clip.");
  auto options = std::make_shared<RomCommandOptions>();
  command->add_option("MODEL", options->model, "a rigged .glb/.gltf/.fbx/.dae model")
      ->type_name("")
      ->required();
  command->add_option("-o", options->out, "the .glb to write")->type_name("OUT.glb")->required();
  command
      ->add_option("--rig", options->rig,
                   "which joints form torso, neck, arms and legs (default: detected)")
      ->type_name("RIG.json");
  command->add_flag("--list", options->list, "list the moves with their frames");
  return {command, [options] { return write_rom(*options); }};
}

}  // namespace sweepd::cli
