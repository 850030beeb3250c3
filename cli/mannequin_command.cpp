// sweepctl mannequin: writes the procedural rigged mannequin (the daemon's default model) as .glb.
#include <chrono>
#include <climits>
#include <cstdio>
#include <filesystem>
#include <string>

#include "cli/commands.h"
#include "cli/text_format.h"
#include "deform/mannequin.h"
#include "io/gltf_save.h"

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

int run_mannequin(const std::vector<std::string>& args) {
  deform::MannequinOptions options;
  std::filesystem::path out;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    const bool has_value = i + 1 < args.size();
    if (arg == "--help" || arg == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (arg == "--vertices" && has_value) {
      const std::string& value = args[++i];
      if (!parse_int(value, INT_MIN, INT_MAX, options.target_vertices)) {
        std::fprintf(stderr, "sweepctl mannequin: --vertices expects a whole number, got '%s'\n",
                     value.c_str());
        return 2;
      }
    } else if (arg == "-o" && has_value) {
      out = args[++i];
    } else {
      std::fprintf(stderr, "sweepctl mannequin: unexpected argument '%s'\n\n", arg.c_str());
      std::fputs(kUsage, stderr);
      return 2;
    }
  }
  if (out.empty()) {
    std::fprintf(stderr, "sweepctl mannequin: missing -o OUT.glb\n\n");
    std::fputs(kUsage, stderr);
    return 2;
  }
  if (options.target_vertices < kMinVertices || options.target_vertices > kMaxVertices) {
    std::fprintf(stderr, "sweepctl mannequin: --vertices %d is outside %d..%d\n",
                 options.target_vertices, kMinVertices, kMaxVertices);
    return 2;
  }
  try {
    const auto start = std::chrono::steady_clock::now();
    const deform::Model model = deform::make_mannequin(options);
    io::save_gltf(model, out);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("wrote %s: %s vertices, %s triangles, %d joints (%.2f s)\n", out.string().c_str(),
                with_thousands(model.vertex_count()).c_str(),
                with_thousands(model.triangle_count()).c_str(), model.skeleton.size(), seconds);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sweepctl mannequin: %s\n", e.what());
    return 1;
  }
}

}  // namespace sweepd::cli
