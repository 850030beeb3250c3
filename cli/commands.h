// The subcommands of sweepctl; each returns the process exit code (0 ok, 1 failed, 2 usage).
#pragma once

#include <string>
#include <vector>

namespace sweepd::cli {

int run_inspect(const std::vector<std::string>& args);
int run_mannequin(const std::vector<std::string>& args);
int run_bind(const std::vector<std::string>& args);
int run_pose(const std::vector<std::string>& args);
int run_render(const std::vector<std::string>& args);
int run_positionmap(const std::vector<std::string>& args);
int run_metrics(const std::vector<std::string>& args);
int run_edit(const std::vector<std::string>& args);

}  // namespace sweepd::cli
