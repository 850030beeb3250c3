// sweepctl mannequin: writes the procedural rigged mannequin (the daemon's default model) as .glb.
#include <chrono>
#include <climits>
#include <cstdio>
#include <filesystem>
#include <string>

#include "cli/commands.h"
#include "cli/subcommand.h"
#include "cli/text_format.h"
#include "io/gltf_save.h"
#include "mannequin/mannequin.h"

namespace sweepd::cli {

namespace {
constexpr const char* kUsage =
    "usage: sweepctl mannequin [--vertices N] -o OUT.glb\n"
    "  --vertices N  approximate vertex count, 2000..300000 (default 20000; the result is\n"
    "                within 10% of N)\n"
    "  -o OUT.glb    where to write the model\n"
    "A rigged humanoid in an A-pose with CMU-style joint names, smooth skin weights, UVs,\n"
    "a closed 2-manifold skin; deterministic for a given N.\n";
constexpr int kMinVertices = 2000;
constexpr int kMaxVertices = 300000;
}  // namespace

int run_mannequin(const std::vector<std::string>& arguments) {
  mannequin::MannequinOptions options;
  std::filesystem::path out;
  auto parse = [&](const std::vector<std::string>& args) -> std::string {
    for (std::size_t i = 0; i < args.size(); ++i) {
      const std::string& arg = args[i];
      const bool has_value = i + 1 < args.size();
      if (arg == "--vertices" && has_value) {
        if (!parse_int(args[++i], INT_MIN, INT_MAX, options.target_vertices))
          return "--vertices expects a whole number, got '" + args[i] + "'";
      } else if (arg == "-o" && has_value) {
        out = args[++i];
      } else {
        return "unexpected argument '" + arg + "'";
      }
    }
    if (out.empty()) return "missing -o OUT.glb";
    if (options.target_vertices < kMinVertices || options.target_vertices > kMaxVertices)
      return "--vertices " + std::to_string(options.target_vertices) + " is outside " +
             std::to_string(kMinVertices) + ".." + std::to_string(kMaxVertices);
    return "";
  };
  return run_subcommand("mannequin", kUsage, arguments, parse, [&] {
    const auto start = std::chrono::steady_clock::now();
    const deform::Model model = mannequin::make_mannequin(options);
    io::save_gltf(model, out);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("wrote %s: %s vertices, %s triangles, %d joints (%.2f s)\n", out.string().c_str(),
                with_thousands(model.vertex_count()).c_str(),
                with_thousands(model.triangle_count()).c_str(), model.skeleton.size(), seconds);
    return 0;
  });
}

}  // namespace sweepd::cli
