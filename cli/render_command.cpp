// sweepctl render: a shaded PNG of a posed model (headless EGL; llvmpipe where there is no
// GPU), optionally coloured by its sweep segmentation — for people to look at deformations.
#include <cstdio>
#include <filesystem>

#include "cli/commands.h"
#include "cli/posed_model.h"
#include "cli/segment_colours.h"
#include "cli/subcommand.h"
#include "cli/text_format.h"
#include "gpu/egl_context.h"
#include "gpu/preview_renderer.h"
#include "io/png_write.h"

namespace sweepd::cli {

namespace {

const std::string kUsage =
    std::string(
        "usage: sweepctl render MODEL [posing options] --png OUT.png [--size N] [--segments]\n"
        "  --png OUT.png      where to write the picture\n"
        "  --size N           image width and height in pixels (default 800)\n"
        "  --segments         colour vertices by sweep (torso, neck, arms, legs) and skinned "
        "parts\n") +
    kPosingUsage;

}  // namespace

int run_render(const std::vector<std::string>& arguments) {
  PosingArguments posing;
  std::filesystem::path png;
  int size = 800;
  bool segments = false;
  auto parse = [&](std::vector<std::string> args) {
    std::string problem = take_posing_arguments(args, posing);
    for (std::size_t i = 0; problem.empty() && i < args.size(); ++i) {
      if (args[i] == "--png" && i + 1 < args.size()) {
        png = args[++i];
      } else if (args[i] == "--size" && i + 1 < args.size()) {
        if (!parse_int(args[++i], 16, 8192, size)) problem = "--size expects 16..8192";
      } else if (args[i] == "--segments") {
        segments = true;
      } else {
        problem = "unexpected argument '" + args[i] + "'";
      }
    }
    if (problem.empty() && png.empty()) problem = "missing --png OUT.png";
    if (problem.empty() && posing.frame_range) problem = "render takes one --frame";
    return problem;
  };
  return run_subcommand("render", kUsage, arguments, parse, [&] {
    PosedModel posed(posing);
    std::vector<glm::vec3> positions, normals, colours;
    posed.deform(posing.frames.first, positions, normals);
    if (segments) colours = segment_colours(posed.bound());
    gpu::Context context;
    gpu::PreviewRenderer renderer(context);
    gpu::PreviewOptions options;
    options.width = options.height = size;
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(size) * size * 4);
    renderer.render({positions, normals, posed.model().indices, colours}, options, rgba);
    io::write_png(png, size, size, rgba);
    std::printf("wrote %s (%dx%d, %s, %s)\n", png.string().c_str(), size, size,
                deform::to_string(posing.method), context.renderer().c_str());
    return 0;
  });
}

}  // namespace sweepd::cli
