// A Z-up BVH clip made from a Y-up one, for tests (issue 15, item 6): the text turned +90° about
// X, (x, y, z) -> (x, -z, y), so that its figure stands along +Z: OFFSET and End Site offsets
// rewritten, Yrotation/Yposition relabelled Z, Zrotation/Zposition relabelled Y with their values
// negated. Numbers are moved and negated as text, so reading it back Y-up
// (motion::turn_z_up_to_y_up) gives the original's values exactly.
//   z_up_bvh(text)    the turned text
//   read_text(file)   a file's bytes
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

namespace sweepd::test {

inline std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline std::string negated(const std::string& number) {
  return number.starts_with('-') ? number.substr(1) : "-" + number;
}

inline std::string z_up_bvh(const std::string& y_up) {
  std::istringstream in(y_up);
  std::ostringstream out;
  std::vector<bool> negate;  // per channel of a data row
  bool rows = false;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string word; words >> word;) w.push_back(word);
    if (rows && !w.empty()) {
      for (std::size_t c = 0; c < w.size(); ++c)
        out << (c ? " " : "") << (negate.at(c) ? negated(w[c]) : w[c]);
      out << "\n";
    } else if (!w.empty() && w[0] == "OFFSET") {
      out << "OFFSET " << w[1] << " " << negated(w[3]) << " " << w[2] << "\n";
    } else if (!w.empty() && w[0] == "CHANNELS") {
      out << "CHANNELS " << w[1];
      for (std::size_t c = 2; c < w.size(); ++c) {
        std::string name = w[c];
        negate.push_back(name[0] == 'Z');
        if (name[0] == 'Y' || name[0] == 'Z') name[0] = name[0] == 'Y' ? 'Z' : 'Y';
        out << " " << name;
      }
      out << "\n";
    } else {
      out << line << "\n";
      rows |= !w.empty() && w[0] == "Frame";
    }
  }
  return out.str();
}

}  // namespace sweepd::test
