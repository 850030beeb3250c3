#include "client/bind_warnings.h"

namespace sweepd::client {

std::vector<std::string> bind_warning_lines(const protocol::ModelInfo& info) {
  std::vector<std::string> lines;
  if (!info.bind_warnings()) return lines;
  const std::string name = info.name() ? info.name()->str() : "";
  for (const protocol::BindWarning* warning : *info.bind_warnings())
    lines.push_back("model '" + name + "': " + (warning->text() ? warning->text()->str() : ""));
  return lines;
}

void print_bind_warnings(std::FILE* out, const protocol::ModelInfo& info) {
  for (const std::string& line : bind_warning_lines(info))
    std::fprintf(out, "warning: %s\n", line.c_str());
}

}  // namespace sweepd::client
