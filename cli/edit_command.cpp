// sweepctl edit: stores key-ellipse edits (paper §4.2; the JSON format is in
// io/json/key_ellipse_edits_json.h) in a bound model's .sweepbind file, replacing the edits it had,
// so every later pose of that model applies them.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli/commands.h"
#include "deform/rig/rig_map.h"
#include "io/json/key_ellipse_edits_json.h"
#include "io/sweepbind/sweepbind.h"

namespace sweepd::cli {

namespace {

struct EditCommandOptions {
  std::filesystem::path model, edits, out;  // out empty: over model
};

int edit(const EditCommandOptions& options) {
  const std::filesystem::path& out = options.out.empty() ? options.model : options.out;
  deform::BoundModel bound = io::load_sweepbind(options.model);
  bound.edits = io::load_key_ellipse_edits_json(options.edits, bound);
  io::save_sweepbind(bound, out);
  std::printf("wrote %s with %zu key ellipse edit(s)\n", out.string().c_str(),
              bound.edits.edits.size());
  for (const deform::KeyEllipseEdit& e : bound.edits.edits)
    std::printf("  %s key %d, driven by %s: %zu sample(s) up to %.0f deg\n",
                deform::to_string(bound.sweeps[e.sweep].part), e.key,
                bound.model.skeleton.joints[e.joint].name.c_str(), e.samples.size(),
                e.samples.back().angle_degrees);
  return 0;
}

}  // namespace

Command add_edit_command(CLI::App& sweepctl) {
  CLI::App* command =
      sweepctl.add_subcommand("edit", "store key-ellipse edits (JSON) in a .sweepbind file");
  auto options = std::make_shared<EditCommandOptions>();
  const CLI::Validator bound_model(
      [](std::string& file) -> std::string {
        if (std::filesystem::path(file).extension() == ".sweepbind") return "";
        return file + " is not a .sweepbind file (bind it first: sweepctl bind)";
      },
      "");
  command->add_option("MODEL", options->model, "a bound model (sweepctl bind): MODEL.sweepbind")
      ->type_name("")
      ->required()
      ->check(bound_model);
  command
      ->add_option("EDITS", options->edits,
                   "key-ellipse edits, EDITS.json (format in io/json/key_ellipse_edits_json.h); they "
                   "replace the model's edits ({\"edits\": []} removes them)")
      ->type_name("")
      ->required();
  command->add_option("-o", options->out, "write there instead of over MODEL")
      ->type_name("OUT.sweepbind");
  return {command, [options] { return edit(*options); }};
}

}  // namespace sweepd::cli
