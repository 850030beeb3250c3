// The command lines of every program a user runs: sweepctl (and its subcommands), the client
// examples stream_poses and render_frames, and server_bench. Each answers --help with its
// usage naming its flags (exit 0) and refuses "12x" where a number is expected with a message
// naming the flag (exit 2). No daemon is needed: a refused command line never connects.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/server/client_run.h"

namespace sweepd::test {
namespace {

struct Program {
  std::string command;              // the program, and a subcommand where it has them
  std::vector<std::string> flags;   // what --help must name
  std::string bad_number;           // arguments with "12x" where a number is expected
  std::string flag_in_the_message;  // the flag the refusal names
};

std::vector<Program> programs() {
  const std::string sweepctl = SWEEPD_SWEEPCTL;
  std::vector<Program> list = {
      {sweepctl,
       {"--server", "--token", "pose"},
       "pose m.glb --bvh c.bvh --frame 12x -o x.glb",
       "--frame"},
      {sweepctl + " pose",
       {"--bvh", "--frame", "--frames", "--method", "--features"},
       "m.glb --bvh c.bvh --frames 12x -o out",
       "--frames"},
      {sweepctl + " mannequin", {"--vertices"}, "--vertices 12x -o x.glb", "--vertices"},
      {sweepctl + " bind",
       {"MODEL", "-o", "--rig", "--keys-per-link", "--debug-gltf"},
       "m.glb -o x.sweepbind --keys-per-link 12x",
       "--keys-per-link"},
      {sweepctl + " render",
       {"--bvh", "--frame", "--pose", "--method", "--features", "--png", "--size", "--segments"},
       "m.glb --size 12x --png x.png",
       "--size"},
      {sweepctl + " positionmap",
       {"--frame", "--method", "-o", "--size", "--gutter", "--normals", "--half-normals",
        "--compression"},
       "m.glb --gutter 12x -o x.exr",
       "--gutter"},
      {sweepctl + " metrics",
       {"--bvh", "--frame", "--frames", "--pose", "--method", "--step", "--json", "--csv"},
       "m.glb --bvh c.bvh --step 12x",
       "--step"},
      {SWEEPD_STREAM_POSES,
       {"--bvh", "--host", "--port", "--frames", "--flat-out", "--latest-wins"},
       "--bvh c.bvh --port 12x",
       "--port"},
      {SWEEPD_STREAM_POSES, {"--frames"}, "--bvh c.bvh --frames 12x", "--frames"},
      {SWEEPD_RENDER_FRAMES,
       {"--server", "--bvh", "--frames", "-o", "--width", "--compression", "--method",
        "--half-normals"},
       "--server h:1 --bvh c.bvh --frames 12x -o out",
       "--frames"},
      {SWEEPD_RENDER_FRAMES,
       {"--height"},
       "--server h:1 --bvh c.bvh --frames 0-1 -o out --width 12x",
       "--width"},
  };
#ifdef SWEEPD_SERVER_BENCH
  list.push_back({SWEEPD_SERVER_BENCH,
                  {"--daemon", "--vertices", "--poses", "--seconds"},
                  "--vertices 12x",
                  "--vertices"});
#endif
  return list;
}

TEST(CommandLines, HelpPrintsTheUsageWithEveryFlagAndExitsZero) {
  for (const Program& program : programs()) {
    const ClientRun run = run_client(program.command + " --help");
    EXPECT_EQ(run.exit_code, 0) << program.command << "\n" << run.output;
    for (const std::string& flag : program.flags)
      EXPECT_NE(run.output.find(flag), std::string::npos)
          << program.command << " --help does not name " << flag << "\n"
          << run.output;
  }
}

TEST(CommandLines, ANumberWithTrailingLettersIsRefusedNamingTheFlag) {
  for (const Program& program : programs()) {
    const ClientRun run = run_client(program.command + " " + program.bad_number);
    EXPECT_EQ(run.exit_code, 2) << program.command << " " << program.bad_number << "\n"
                                << run.output;
    EXPECT_NE(run.output.find(program.flag_in_the_message), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("12x"), std::string::npos) << run.output;
  }
}

}  // namespace
}  // namespace sweepd::test
