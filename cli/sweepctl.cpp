// sweepctl: the user's command line. Each subcommand lives in its own *_command.cpp.
// `--server HOST:PORT [--token T]`, before or after the subcommand, runs pose, positionmap and
// metrics on a sweepd daemon instead of in this process.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/remote_posed_model.h"

namespace {

using sweepd::cli::ServerAddress;

struct Command {
  const char* name;
  const char* summary;
  int (*run)(const std::vector<std::string>& args);
  // The command on a sweepd daemon (--server), or nullptr when it runs locally only.
  int (*run_on_server)(const std::vector<std::string>& args, const ServerAddress& server);
};

const Command kCommands[] = {
    {"inspect", "counts, joint tree, UVs, bounds and weights of a .glb/.gltf/.bvh file",
     sweepd::cli::run_inspect, nullptr},
    {"mannequin", "generate the procedural rigged mannequin as .glb", sweepd::cli::run_mannequin,
     nullptr},
    {"bind", "bind a rigged model to its control sweeps, write .sweepbind", sweepd::cli::run_bind,
     nullptr},
    {"pose", "deform a model into a pose or clip frames, write .glb", sweepd::cli::run_pose,
     sweepd::cli::run_pose_on_server},
    {"render", "shaded PNG preview of a posed model (headless EGL)", sweepd::cli::run_render,
     nullptr},
    {"positionmap", "posed positions in UV space as an OpenEXR map", sweepd::cli::run_positionmap,
     sweepd::cli::run_positionmap_on_server},
    {"metrics", "volume, section, crossing and stretch metrics per method",
     sweepd::cli::run_metrics, sweepd::cli::run_metrics_on_server},
    {"edit", "store key-ellipse edits (JSON) in a .sweepbind file", sweepd::cli::run_edit, nullptr},
};

void print_usage(std::FILE* out) {
  std::fprintf(out,
               "usage: sweepctl [--server HOST:PORT [--token T]] COMMAND [ARGS...]\n"
               "       (sweepctl COMMAND --help for details)\n\n");
  for (const Command& c : kCommands) std::fprintf(out, "  %-12s %s\n", c.name, c.summary);
  std::fprintf(
      out,
      "\n  --server HOST:PORT  run pose, positionmap or metrics on a sweepd daemon: MODEL\n"
      "                      is a local .glb/.gltf (uploaded) or a model name there\n"
      "  --token T           the daemon's auth token\n");
}

// Takes --server HOST:PORT and --token T out of args (anywhere). Returns "" or the problem.
std::string take_server_options(std::vector<std::string>& args, ServerAddress& server,
                                bool& remote) {
  std::vector<std::string> rest;
  bool token_given = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const bool has_value = i + 1 < args.size();
    if ((args[i] == "--server" || args[i] == "--token") && !has_value) {
      return args[i] + " expects a value";
    } else if (args[i] == "--server") {
      server.address = args[++i];
      remote = true;
    } else if (args[i] == "--token") {
      server.token = args[++i];
      token_given = true;
    } else {
      rest.push_back(args[i]);
    }
  }
  args = std::move(rest);
  if (token_given && !remote) return "--token needs --server HOST:PORT";
  return {};
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  ServerAddress server;
  bool remote = false;
  if (const std::string problem = take_server_options(args, server, remote); !problem.empty()) {
    std::fprintf(stderr, "sweepctl: %s\n\n", problem.c_str());
    print_usage(stderr);
    return 2;
  }
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    print_usage(args.empty() ? stderr : stdout);
    return args.empty() ? 2 : 0;
  }
  const std::string name = args[0];
  args.erase(args.begin());
  for (const Command& c : kCommands) {
    if (name != c.name) continue;
    if (!remote) return c.run(args);
    if (c.run_on_server) return c.run_on_server(args, server);
    std::fprintf(stderr,
                 "sweepctl %s: runs locally only; --server applies to pose, "
                 "positionmap and metrics\n",
                 c.name);
    return 2;
  }
  std::fprintf(stderr, "sweepctl: unknown command '%s'\n\n", name.c_str());
  print_usage(stderr);
  return 2;
}
