// The subcommands of sweepctl; each returns the process exit code (0 ok, 1 failed, 2 usage).
#pragma once

#include <string>
#include <vector>

namespace sweepd::cli {

struct ServerAddress;  // cli/remote_posed_model.h

int run_inspect(const std::vector<std::string>& args);
int run_mannequin(const std::vector<std::string>& args);
int run_bind(const std::vector<std::string>& args);
int run_pose(const std::vector<std::string>& args);
int run_render(const std::vector<std::string>& args);
int run_positionmap(const std::vector<std::string>& args);
int run_metrics(const std::vector<std::string>& args);
int run_edit(const std::vector<std::string>& args);

// The same commands deformed by a sweepd daemon (sweepctl --server HOST:PORT [--token T] ...).
int run_pose_on_server(const std::vector<std::string>& args, const ServerAddress& server);
int run_positionmap_on_server(const std::vector<std::string>& args, const ServerAddress& server);
int run_metrics_on_server(const std::vector<std::string>& args, const ServerAddress& server);

}  // namespace sweepd::cli
