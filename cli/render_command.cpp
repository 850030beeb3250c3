// sweepctl render: a shaded PNG of a posed model (headless EGL; llvmpipe where there is no
// GPU), optionally coloured by its sweep segmentation — for people to look at deformations.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli/commands.h"
#include "cli/posed_model.h"
#include "cli/segment_colours.h"
#include "console/command_line.h"
#include "gpu/egl_context.h"
#include "gpu/preview_renderer.h"
#include "io/png/png_write.h"

namespace sweepd::cli {

namespace {

struct RenderCommandOptions {
  PosingArguments posing;
  std::filesystem::path png;
  int size = 800;
  bool segments = false;
};

int render(const RenderCommandOptions& options) {
  const PosingArguments& posing = options.posing;
  const int size = options.size;
  PosedModel posed(posing);
  std::vector<glm::vec3> positions, normals, colours;
  posed.deform(posing.frames.first, positions, normals);
  if (options.segments) colours = segment_colours(posed.bound());
  gpu::Context context;
  gpu::PreviewRenderer renderer(context);
  gpu::PreviewOptions preview;
  preview.width = preview.height = size;
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(size) * size * 4);
  renderer.render({positions, normals, posed.model().indices, colours}, preview, rgba);
  io::write_png(options.png, size, size, rgba);
  std::printf("wrote %s (%dx%d, %s, %s)\n", options.png.string().c_str(), size, size,
              deform::to_string(posing.method), context.renderer().c_str());
  return 0;
}

}  // namespace

Command add_render_command(CLI::App& sweepctl) {
  CLI::App* command =
      sweepctl.add_subcommand("render", "shaded PNG preview of a posed model (headless EGL)");
  auto options = std::make_shared<RenderCommandOptions>();
  add_posing_flags(*command, options->posing, ClipFrames::kOne);
  add_method_flags(*command, options->posing);
  command->add_option("--png", options->png, "where to write the picture")
      ->type_name("OUT.png")
      ->required();
  command->add_option("--size", options->size, "image width and height in pixels")
      ->type_name("N")
      ->check(console::whole_number(16, 8192))
      ->capture_default_str();
  command->add_flag("--segments", options->segments,
                    "colour vertices by sweep (torso, neck, arms, legs) and skinned parts");
  command->callback([options] { check_method_flags(options->posing); });
  return {command, [options] { return render(*options); }};
}

}  // namespace sweepd::cli
