#include "io/json/json_file.h"

#include <fstream>

#include "io/files/load_error.h"

namespace sweepd::io {

nlohmann::json read_json_file(const std::filesystem::path& path, const std::string& what) {
  std::ifstream file(path);
  if (!file) throw LoadError(path, "cannot open the " + what);
  try {
    return nlohmann::json::parse(file);
  } catch (const nlohmann::json::parse_error& e) {
    throw LoadError(path, "the " + what + " is not valid JSON: " + e.what());
  }
}

}  // namespace sweepd::io
