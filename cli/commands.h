// sweepctl's commands, one per *_command.cpp. Each add_*_command adds its subcommand to the
// sweepctl CLI::App — its flags, bound to the command's own options, and the description a
// person reads with `sweepctl COMMAND --help` — and returns how to run it once the command
// line is parsed (console::parse_command_line):
//   rules between flags   the subcommand's CLI11 callback, at the end of the parse; throws
//                         CLI::ValidationError (a usage error: exit 2)
//   run                   the work; returns the exit code (0), or throws std::exception naming
//                         the file and the reason (input the work refuses: exit 1)
// pose, positionmap, metrics and sheet also run on a sweepd daemon: they read the top-level
// `--server HOST:PORT [--token T]` from `server` (address empty: run here), which is filled by
// the time their callback and run are called, wherever --server stood on the line.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace sweepd::cli {

struct ServerAddress;  // cli/remote_posed_model.h

struct Command {
  CLI::App* app = nullptr;  // the subcommand, owned by the sweepctl App
  std::function<int()> run;
  bool runs_on_server = false;  // whether --server applies
};

Command add_inspect_command(CLI::App& sweepctl);
Command add_mannequin_command(CLI::App& sweepctl);
Command add_bind_command(CLI::App& sweepctl);
Command add_pose_command(CLI::App& sweepctl, const ServerAddress& server);
Command add_render_command(CLI::App& sweepctl);
Command add_positionmap_command(CLI::App& sweepctl, const ServerAddress& server);
Command add_metrics_command(CLI::App& sweepctl, const ServerAddress& server);
Command add_edit_command(CLI::App& sweepctl);
Command add_sheet_command(CLI::App& sweepctl, const ServerAddress& server);
Command add_check_command(CLI::App& sweepctl);
Command add_rom_command(CLI::App& sweepctl);
Command add_join_cache_command(CLI::App& sweepctl);

}  // namespace sweepd::cli
