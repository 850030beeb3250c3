// sweepctl: the user's command line. Each subcommand lives in its own *_command.cpp.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "cli/commands.h"

namespace {

struct Command {
  const char* name;
  const char* summary;
  int (*run)(const std::vector<std::string>& args);
};

const Command kCommands[] = {
    {"inspect", "counts, joint tree, UVs, bounds and weights of a .glb/.gltf/.bvh file",
     sweepd::cli::run_inspect},
    {"mannequin", "generate the procedural rigged mannequin as .glb", sweepd::cli::run_mannequin},
    {"bind", "bind a rigged model to its control sweeps, write .sweepbind", sweepd::cli::run_bind},
    {"pose", "deform a model into a pose or clip frames, write .glb", sweepd::cli::run_pose},
    {"render", "shaded PNG preview of a posed model (headless EGL)", sweepd::cli::run_render},
    {"positionmap", "posed positions in UV space as an OpenEXR map", sweepd::cli::run_positionmap},
    {"metrics", "volume, section, crossing and stretch metrics per method", sweepd::cli::run_metrics},
    {"edit", "store key-ellipse edits (JSON) in a .sweepbind file", sweepd::cli::run_edit},
};

void print_usage(std::FILE* out) {
  std::fprintf(out,
               "usage: sweepctl COMMAND [ARGS...]   (sweepctl COMMAND --help for details)\n\n");
  for (const Command& c : kCommands) std::fprintf(out, "  %-12s %s\n", c.name, c.summary);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    print_usage(argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  const std::vector<std::string> args(argv + 2, argv + argc);
  for (const Command& c : kCommands)
    if (std::strcmp(argv[1], c.name) == 0) return c.run(args);
  std::fprintf(stderr, "sweepctl: unknown command '%s'\n\n", argv[1]);
  print_usage(stderr);
  return 2;
}
