// sweepctl mannequin: writes the procedural rigged mannequin (the daemon's default model) as .glb.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli/commands.h"
#include "console/text_format.h"
#include "console/command_line.h"
#include "io/gltf/gltf_save.h"
#include "mannequin/mannequin.h"

namespace sweepd::cli {

Command add_mannequin_command(CLI::App& sweepctl) {
  CLI::App* command =
      sweepctl.add_subcommand("mannequin", "generate the procedural rigged mannequin as .glb");
  command->footer(
      "A rigged humanoid in an A-pose with CMU-style joint names, smooth skin weights, UVs,\n"
      "a closed 2-manifold skin; deterministic for a given N.");
  struct MannequinCommandOptions {
    mannequin::MannequinOptions mannequin;
    std::filesystem::path out;
  };
  auto options = std::make_shared<MannequinCommandOptions>();
  command
      ->add_option("--vertices", options->mannequin.target_vertices,
                   "approximate vertex count (the result is within 10% of N)")
      ->type_name("N")
      ->check(console::whole_number(2000, 300000))
      ->capture_default_str();
  command->add_option("-o", options->out, "where to write the model")
      ->type_name("OUT.glb")
      ->required();
  return {command, [options] {
            const auto start = std::chrono::steady_clock::now();
            const deform::Model model = mannequin::make_mannequin(options->mannequin);
            io::save_gltf(model, options->out);
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            std::printf("wrote %s: %s vertices, %s triangles, %d joints (%.2f s)\n",
                        options->out.string().c_str(), console::with_thousands(model.vertex_count()).c_str(),
                        console::with_thousands(model.triangle_count()).c_str(), model.skeleton.size(),
                        seconds);
            return 0;
          }};
}

}  // namespace sweepd::cli
