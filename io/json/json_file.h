// JSON file reading for io/'s small hand-written formats: opens and parses a file, turning
// every failure into a LoadError that names the file.
//
//   path  the file; what  how error messages call it ("pose file", "joint name map")
// Returns the parsed document (any JSON value; the caller checks its shape).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace sweepd::io {

nlohmann::json read_json_file(const std::filesystem::path& path, const std::string& what);

}  // namespace sweepd::io
