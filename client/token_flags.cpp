#include "client/token_flags.h"

#include <fstream>

namespace sweepd::client {

void add_token_flags(CLI::App& app, std::string& token, CLI::Option* needs) {
  CLI::Option* given = app.add_option("--token", token, "the daemon's auth token")->type_name("T");
  CLI::Option* file =
      app.add_option_function<std::string>(
             "--token-file",
             [&token](const std::string& path) {
               std::ifstream in(path);
               if (!in) throw CLI::ValidationError("--token-file", path + ": cannot read the file");
               std::getline(in, token);
             },
             "read the token from the first line of FILE (e.g. a mounted Secret)")
          ->type_name("FILE");
  given->excludes(file);
  if (needs != nullptr) {
    given->needs(needs);
    file->needs(needs);
  }
}

}  // namespace sweepd::client
