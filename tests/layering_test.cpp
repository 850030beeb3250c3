// The layers' include rules: docs/architecture.md's table "Include rules" is an allow-list, and
// every `#include "folder/..."` of every .h and .cpp file of every folder of the tree must be in
// its folder's row (or name a file of the same row). A folder with C++ files and no row fails
// too, so a new folder gets its rules before its first include. deform/'s top level holds only
// its stage folders and README.md. Reads the source as text.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "tests/test_paths.h"

namespace {

namespace fs = std::filesystem;
const fs::path kSource = SWEEPD_SOURCE_DIR;

// One row of the table: the folders and files its folder may include; `anything` for tests/.
struct IncludeRule {
  std::vector<std::string> allowed;  // "deform/" (a folder) or "deform/job/method_choice.h"
  bool anything = false;
};

// The rows of docs/architecture.md's table "Include rules", by folder ("gpu/sheet/").
std::map<std::string, IncludeRule> include_rules() {
  std::ifstream in(kSource / "docs/architecture.md");
  std::string line;
  while (std::getline(in, line) && line != "## Include rules") {
  }
  std::map<std::string, IncludeRule> rules;
  static const std::regex row(R"re(^\| `([^`]+/)` \| ([^|]*) \|)re");
  static const std::regex entry("`([^`]+)`");
  while (std::getline(in, line) && !line.starts_with("## ")) {
    std::smatch match;
    if (!std::regex_search(line, match, row)) continue;
    IncludeRule rule;
    const std::string cell = match[2];
    rule.anything = cell.find("anything") != std::string::npos;
    for (auto it = std::sregex_iterator(cell.begin(), cell.end(), entry);
         it != std::sregex_iterator(); ++it)
      rule.allowed.push_back((*it)[1]);
    rules[match[1]] = rule;
  }
  return rules;
}

// The row that holds for `path` (relative to the source, "gpu/sheet/contact_sheet.h"): the
// longest folder of the table it lies in; "" when none.
std::string row_of(const std::map<std::string, IncludeRule>& rules, const std::string& path) {
  std::string best;
  for (const auto& [folder, rule] : rules)
    if (path.starts_with(folder) && folder.size() > best.size()) best = folder;
  return best;
}

bool allowed_by(const IncludeRule& rule, const std::string& included) {
  if (rule.anything) return true;
  for (const std::string& entry : rule.allowed)
    if (entry.ends_with("/") ? included.starts_with(entry) : included == entry) return true;
  return false;
}

bool is_cpp(const fs::path& file) {
  const std::string ext = file.extension().string();
  return ext == ".h" || ext == ".cpp";
}

// The top-level folders of the tree (not build trees, not hidden ones).
std::vector<std::string> top_folders() {
  std::vector<std::string> folders;
  for (const auto& entry : fs::directory_iterator(kSource)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_directory() && !name.starts_with(".") && !name.starts_with("build"))
      folders.push_back(name);
  }
  return folders;
}

// Every quoted include of a tree folder that the includer's row does not allow, as
// "file: include"; every folder with C++ files and no row, as "folder/: no row".
std::vector<std::string> includes_outside_the_rules(
    const std::map<std::string, IncludeRule>& rules) {
  static const std::regex include(R"re(^\s*#\s*include\s*"(([^/"]+)/[^"]*)")re");
  const std::vector<std::string> folders = top_folders();
  const std::set<std::string> tops(folders.begin(), folders.end());
  std::vector<std::string> found;
  std::set<std::string> without_row;
  for (const std::string& folder : folders) {
    for (auto it = fs::recursive_directory_iterator(kSource / folder);
         it != fs::recursive_directory_iterator(); ++it) {
      if (it->is_directory() && it->path().filename() == "node_modules") {
        it.disable_recursion_pending();
        continue;
      }
      if (!it->is_regular_file() || !is_cpp(it->path())) continue;
      const std::string file = fs::relative(it->path(), kSource).string();
      const std::string row = row_of(rules, file);
      if (row.empty()) {
        without_row.insert(folder + "/");
        continue;
      }
      std::ifstream in(it->path());
      std::string line;
      std::smatch match;
      while (std::getline(in, line)) {
        if (!std::regex_search(line, match, include) || !tops.contains(match[2])) continue;
        const std::string included = match[1];
        if (row_of(rules, included) == row || allowed_by(rules.at(row), included)) continue;
        found.push_back(file + ": " + line);
      }
    }
  }
  for (const std::string& folder : without_row) found.push_back(folder + ": no row");
  return found;
}

TEST(Layering, EveryIncludeOfEveryFolderIsInItsRowOfTheIncludeRules) {
  const std::map<std::string, IncludeRule> rules = include_rules();
  // deform/ to tests/: a table cut short reads as fewer rules, not as a pass.
  ASSERT_GE(rules.size(), 17u) << "docs/architecture.md: the table \"Include rules\" is missing";
  for (const char* folder : {"deform/", "client/", "gpu/", "fuzz/", "bench/", "cli/",
                             "client_examples/", "selfcheck/", "console/", "tests/"})
    EXPECT_TRUE(rules.contains(folder)) << folder << " has no row";
  const std::vector<std::string> found = includes_outside_the_rules(rules);
  std::string listing;
  for (const std::string& f : found) listing += "\n  " + f;
  EXPECT_TRUE(found.empty()) << "includes outside docs/architecture.md's include rules:" << listing;
}

TEST(Layering, TheRulesRefuseAnIncludeOutsideTheirRow) {
  const std::map<std::string, IncludeRule> rules = include_rules();
  ASSERT_TRUE(rules.contains("deform/") && rules.contains("gpu/") && rules.contains("bench/"));
  EXPECT_FALSE(allowed_by(rules.at("deform/"), "io/gltf/gltf_load.h"));
  EXPECT_FALSE(allowed_by(rules.at("gpu/"), "metrics/quality_metrics.h"));
  EXPECT_TRUE(allowed_by(rules.at("gpu/sheet/"), "metrics/quality_metrics.h"));
  // A subfolder's row is its own: gpu/ may not include gpu/sheet/.
  EXPECT_EQ(row_of(rules, "gpu/sheet/contact_sheet.h"), "gpu/sheet/");
  EXPECT_EQ(row_of(rules, "gpu/camera.h"), "gpu/");
  // Of tests/, bench/ may include the test helpers only.
  EXPECT_TRUE(allowed_by(rules.at("bench/"), "tests/test_paths.h"));
  EXPECT_FALSE(allowed_by(rules.at("bench/"), "tests/server/daemon_process.h"));
  EXPECT_FALSE(allowed_by(rules.at("client/"), "deform/model/model.h"));
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
