// The layers' include rules (docs/architecture.md "Layout", deform/README.md): deform/ is the paper and
// includes nothing from the layers built on it; mannequin/, metrics/ and motion/ stand on
// deform/ only; console/ stands alone; protocol/ never includes deform/; nothing includes
// server/ but server/ itself.
// selfcheck/ stands on deform/, motion/ and metrics/.
// deform/'s top level holds only its stage folders and README.md. Reads the source as text.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
const fs::path kSource = SWEEPD_SOURCE_DIR;

// Every `#include "top/..."` of the C++ files below `folder`, as "file: include".
std::vector<std::string> includes_of(const std::string& folder,
                                     const std::vector<std::string>& forbidden) {
  static const std::regex include(R"re(^\s*#\s*include\s*"([^/"]+)/[^"]*")re");
  std::vector<std::string> found;
  for (const auto& entry : fs::recursive_directory_iterator(kSource / folder)) {
    const std::string ext = entry.path().extension().string();
    if (!entry.is_regular_file() || (ext != ".h" && ext != ".cpp")) continue;
    std::ifstream in(entry.path());
    std::string line;
    std::smatch match;
    while (std::getline(in, line))
      if (std::regex_search(line, match, include))
        for (const std::string& top : forbidden)
          if (match[1] == top)
            found.push_back(fs::relative(entry.path(), kSource).string() + ": " + line);
  }
  return found;
}

TEST(Layering, EachLayerIncludesOnlyTheLayersBelowIt) {
  const std::map<std::string, std::vector<std::string>> forbidden = {
      {"deform",
       {"mannequin", "metrics", "motion", "selfcheck", "io", "gpu", "protocol", "client", "server", "cli"}},
      {"mannequin", {"metrics", "motion", "selfcheck", "io", "gpu", "protocol", "client", "server", "cli"}},
      {"metrics", {"mannequin", "motion", "selfcheck", "io", "gpu", "protocol", "client", "server", "cli"}},
      {"motion", {"mannequin", "metrics", "selfcheck", "io", "gpu", "protocol", "client", "server", "cli"}},
      // selfcheck/ (the binding's self-check) stands on deform, motion and metrics.
      {"selfcheck", {"mannequin", "io", "gpu", "protocol", "client", "server", "cli"}},
      {"protocol", {"deform", "mannequin", "metrics", "motion", "io", "gpu", "server", "cli"}},
      {"io", {"gpu", "protocol", "client", "server", "cli"}},
      {"gpu", {"protocol", "client", "server", "cli"}},
      {"cli", {"server"}},
      {"console",
       {"deform", "mannequin", "metrics", "motion", "io", "gpu", "protocol", "client", "server",
        "cli"}},
      {"client", {"server", "cli"}},
      // fuzz/ sits on top of everything it fuzzes; nothing below includes it.
      {"server", {"fuzz", "cli"}},
  };
  for (const auto& [folder, tops] : forbidden) {
    if (!fs::exists(kSource / folder)) continue;  // a layer not (yet) in the tree
    const std::vector<std::string> found = includes_of(folder, tops);
    std::string listing;
    for (const std::string& f : found) listing += "\n  " + f;
    EXPECT_TRUE(found.empty()) << folder << "/ includes a layer above it:" << listing;
  }
}

TEST(Layering, DeformTopLevelHoldsOnlyStageFoldersAndItsReadme) {
  std::vector<std::string> files;
  int folders = 0;
  for (const auto& entry : fs::directory_iterator(kSource / "deform")) {
    if (entry.is_directory())
      ++folders;
    else
      files.push_back(entry.path().filename().string());
  }
  ASSERT_EQ(files.size(), 1u) << "deform/ top level must hold README.md alone";
  EXPECT_EQ(files[0], "README.md");
  // sweep, binding, blending, posing, edits, features, volume, job, baselines, rig, model,
  // mesh, simd: at least the paper's seven stages.
  EXPECT_GE(folders, 7);
}

}  // namespace
