// sweepctl: the user's command line — one CLI::App (console/command_line.h) with a subcommand
// per command, each declared in its own *_command.cpp (cli/commands.h).
// `--server HOST:PORT [--token T] [--tls ...]`, before or after the command, runs pose,
// positionmap, metrics and sheet on a sweepd daemon instead of in this process.
#include <cstdio>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/remote_posed_model.h"
#include "client/client_tls_flags.h"
#include "client/token_flags.h"
#include "console/command_line.h"

int main(int argc, char** argv) {
  using namespace sweepd;
  cli::ServerAddress server;
  CLI::App app("Binds rigged models to control sweeps, poses, renders and measures them.",
               "sweepctl");
  app.get_formatter()->column_width(36);  // shared with the commands
  app.fallthrough();                      // --server and --token also after the command
  app.require_subcommand(0, 1);           // one command; a second command name is an argument
  // A flag given twice takes its last value (every command inherits the default).
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  CLI::Option* server_flag =
      app.add_option("--server", server.address)->type_name("HOST:PORT");  // described below
  client::add_token_flags(app, server.token, server_flag);
  client::add_client_tls_flags(app, server.tls, server_flag);
  const std::vector<cli::Command> commands = {cli::add_inspect_command(app),
                                              cli::add_mannequin_command(app),
                                              cli::add_bind_command(app),
                                              cli::add_pose_command(app, server),
                                              cli::add_render_command(app),
                                              cli::add_positionmap_command(app, server),
                                              cli::add_metrics_command(app, server),
                                              cli::add_edit_command(app),
                                              cli::add_sheet_command(app, server),
                                              cli::add_check_command(app),
                                              cli::add_rom_command(app),
                                              cli::add_join_cache_command(app)};
  // Set after the commands are added: a subcommand inherits its parent's footer.
  app.footer("sweepctl COMMAND --help lists the command's flags.");
  // The commands --server applies to, named from the commands themselves so that the help and
  // the refusal cannot drift from what runs remotely.
  std::vector<std::string> remote;
  for (const cli::Command& command : commands)
    if (command.runs_on_server) remote.push_back(command.app->get_name());
  std::string remote_commands = remote.front();  // "pose, positionmap, metrics and sheet"
  for (std::size_t i = 1; i < remote.size(); ++i)
    remote_commands += (i + 1 < remote.size() ? ", " : " and ") + remote[i];
  server_flag->description("run " + remote_commands +
                           " on a sweepd daemon: MODEL is a local .glb/.gltf/.fbx/.dae (uploaded) "
                           "or a model name there");
  app.callback([&] {
    for (const cli::Command& command : commands)
      if (command.app->parsed() && !server.address.empty() && !command.runs_on_server)
        throw CLI::ValidationError("runs locally only; --server applies to " + remote_commands);
  });
  if (const std::optional<int> exit_code = console::parse_command_line(app, argc, argv))
    return *exit_code;
  for (const cli::Command& command : commands) {
    if (!command.app->parsed()) continue;
    try {
      return command.run();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "sweepctl %s: %s\n", command.app->get_name().c_str(), e.what());
      return 1;
    }
  }
  return 2;  // not reached: parse_command_line answers a line without a command
}
