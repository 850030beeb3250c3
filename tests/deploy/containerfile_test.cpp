// deploy/Containerfile, linted offline — no linter for it is packaged in Debian 12 (hadolint is
// not; buildah and podman parse a file only by building it) — by parsing its instructions and
// checking what deploy/README.md promises: a Debian 12 base, two stages (the build stage runs
// deploy/install-deps.sh, the runtime one copies the binaries from it), a non-root USER, the
// store as a VOLUME, the protocol and side ports EXPOSEd, a HEALTHCHECK with curl on /readyz of
// the side port, sweepd as ENTRYPOINT with a CMD that sweepd's own flag parser accepts; and
// that the runtime stage installs the Debian package of every shared library the built sweepd
// and render_frames load (ldd + dpkg -S here).
// Then podman: where it can run a container, the image could be built and started; this test
// probes it with a one-file image and, where it cannot (no podman, or — on this project's
// machine — crun refused: no CAP_SYS_RESOURCE for setrlimit, cgroups v1/v2 hybrid), skips
// printing podman's own reason.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>

#include "server/config.h"
#include "tests/deploy/shell_command.h"
#include "tests/server/daemon_process.h"
#include "tests/server/http_probe.h"

namespace sweepd::test {
namespace {

const fs::path kContainerfile = fs::path(SWEEPD_SOURCE_DIR) / "deploy" / "Containerfile";

struct Instruction {
  std::string keyword;    // upper case: FROM, RUN, ...
  std::string arguments;  // continuation lines joined, comments dropped
  int stage = 0;          // 1 for the first FROM's stage, ...
};

// The file's instructions as a builder reads them: `\` continues a line, `#` lines are comments
// (also inside a continued instruction), blank lines are skipped.
std::vector<Instruction> parse_containerfile(const fs::path& file) {
  std::ifstream in(file);
  std::vector<Instruction> instructions;
  std::string pending;
  int stage = 0;
  for (std::string line; std::getline(in, line);) {
    const std::size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos || line[start] == '#') continue;
    line = line.substr(start);
    const bool continued = !line.empty() && line.back() == '\\';
    if (continued) line.pop_back();
    pending += (pending.empty() ? "" : " ") + line;
    if (continued) continue;
    const std::size_t space = pending.find(' ');
    Instruction instruction{pending.substr(0, space),
                            space == std::string::npos ? "" : pending.substr(space + 1), 0};
    for (char& c : instruction.keyword) c = static_cast<char>(std::toupper(c));
    if (instruction.keyword == "FROM") ++stage;
    instruction.stage = stage;
    instructions.push_back(instruction);
    pending.clear();
  }
  return instructions;
}

// The words of an exec-form (JSON array) argument list.
std::vector<std::string> exec_form(const std::string& arguments) {
  const nlohmann::json words = nlohmann::json::parse(arguments, nullptr, false);
  if (!words.is_array()) return {};
  return words.get<std::vector<std::string>>();
}

class ContainerfileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    instructions_ = parse_containerfile(kContainerfile);
    for (const Instruction& instruction : instructions_) {
      stages_ = std::max(stages_, instruction.stage);
    }
  }
  // The instructions of one stage with that keyword.
  std::vector<Instruction> find(const std::string& keyword, int stage) const {
    std::vector<Instruction> found;
    for (const Instruction& instruction : instructions_) {
      if (instruction.keyword == keyword && instruction.stage == stage)
        found.push_back(instruction);
    }
    return found;
  }
  std::string last(const std::string& keyword) const {
    const auto found = find(keyword, stages_);
    return found.empty() ? "" : found.back().arguments;
  }

  std::vector<Instruction> instructions_;
  int stages_ = 0;
};

TEST_F(ContainerfileTest, EveryInstructionIsOneABuilderKnows) {
  const std::set<std::string> known = {"FROM",        "RUN",     "CMD",  "LABEL",      "EXPOSE",
                                       "ENV",         "ADD",     "COPY", "ENTRYPOINT", "VOLUME",
                                       "USER",        "WORKDIR", "ARG",  "ONBUILD",    "STOPSIGNAL",
                                       "HEALTHCHECK", "SHELL"};
  ASSERT_FALSE(instructions_.empty());
  for (const Instruction& instruction : instructions_) {
    EXPECT_TRUE(known.contains(instruction.keyword)) << instruction.keyword;
  }
}

TEST_F(ContainerfileTest, TwoStagesOnDebian12WithTheProjectsInstallerInTheBuildStage) {
  // ARG BASE=<a Debian 12 image> before the first FROM, and every stage FROM it.
  ASSERT_EQ(instructions_.front().keyword, "ARG");
  EXPECT_TRUE(std::regex_search(instructions_.front().arguments,
                                std::regex(R"(^BASE=.*debian:(12|bookworm))")))
      << instructions_.front().arguments;
  ASSERT_EQ(stages_, 2);
  EXPECT_EQ(find("FROM", 1).at(0).arguments, "${BASE} AS build");
  EXPECT_EQ(find("FROM", 2).at(0).arguments, "${BASE}");
  bool installer = false;
  for (const Instruction& run : find("RUN", 1)) {
    installer |= run.arguments.find("deploy/install-deps.sh") != std::string::npos;
  }
  EXPECT_TRUE(installer) << "the build stage does not run deploy/install-deps.sh";
  bool from_build = false;
  for (const Instruction& copy : find("COPY", 2)) {
    from_build |= copy.arguments.starts_with("--from=build ") &&
                  copy.arguments.find("/server/sweepd") != std::string::npos;
  }
  EXPECT_TRUE(from_build) << "the runtime stage does not copy sweepd from the build stage";
  EXPECT_TRUE(find("RUN", 2).size() >= 1);
  for (const Instruction& run : find("RUN", 2)) {
    EXPECT_EQ(run.arguments.find("install-deps.sh"), std::string::npos)
        << "the runtime stage installs the build dependencies";
  }
}

TEST_F(ContainerfileTest, RunsSweepdAsANonRootUserWithTheStoreHealthCheckAndPortsAgreeing) {
  const std::string user = last("USER");
  ASSERT_FALSE(user.empty()) << "no USER in the runtime stage: it would run as root";
  EXPECT_NE(user.substr(0, user.find(':')), "root");
  EXPECT_NE(user.substr(0, user.find(':')), "0");

  EXPECT_EQ(exec_form(last("ENTRYPOINT")), std::vector<std::string>{"sweepd"});
  const std::vector<std::string> command = exec_form(last("CMD"));
  ASSERT_FALSE(command.empty()) << last("CMD");
  const std::vector<std::string_view> views(command.begin(), command.end());
  const server::ServerConfig config = server::parse_server_config(views);

  const std::vector<std::string> volumes = exec_form(last("VOLUME"));
  EXPECT_NE(std::find(volumes.begin(), volumes.end(), config.store_dir.string()), volumes.end())
      << "the store (" << config.store_dir << ") is not a VOLUME";
  std::istringstream exposed(last("EXPOSE"));
  std::set<int> ports;
  for (std::string port; exposed >> port;) ports.insert(std::stoi(port));
  EXPECT_TRUE(ports.contains(config.port));
  ASSERT_GT(config.http_port, 0) << "CMD opens no HTTP side port";
  EXPECT_TRUE(ports.contains(config.http_port));

  const std::string health = last("HEALTHCHECK");
  const std::size_t cmd = health.find("CMD ");
  ASSERT_NE(cmd, std::string::npos) << health;
  const std::vector<std::string> probe = exec_form(health.substr(cmd + 4));
  ASSERT_FALSE(probe.empty()) << health;
  EXPECT_EQ(probe.front(), "curl");
  // -f (alone or in a group such as -fsS): without it curl exits 0 on a 503.
  EXPECT_TRUE(std::any_of(probe.begin(), probe.end(), [](const std::string& word) {
    return word.starts_with("-") && !word.starts_with("--") && word.find('f') != std::string::npos;
  })) << health;
  const std::string url = "http://127.0.0.1:" + std::to_string(config.http_port) + "/readyz";
  EXPECT_NE(std::find(probe.begin(), probe.end(), url), probe.end()) << health;
}

// The shared libraries `binary` loads (ldd's resolved paths).
std::vector<std::string> loaded_libraries(const std::string& binary) {
  std::istringstream lines(run_command("ldd '" + binary + "'").output);
  std::vector<std::string> paths;
  for (std::string line; std::getline(lines, line);) {
    const std::size_t arrow = line.find("=> /");
    if (arrow != std::string::npos) {
      paths.push_back(line.substr(arrow + 3, line.find(' ', arrow + 3) - arrow - 3));
    }
  }
  return paths;
}

TEST_F(ContainerfileTest, RuntimeStageInstallsThePackageOfEveryLibraryTheBinariesLoad) {
  if (!have_program("dpkg") || !have_program("ldd")) GTEST_SKIP() << "no dpkg or ldd here";
  std::string runtime_packages;
  for (const Instruction& run : find("RUN", stages_)) runtime_packages += " " + run.arguments + " ";
  for (const char* binary : {SWEEPD_DAEMON, SWEEPD_RENDER_FRAMES}) {
    const std::vector<std::string> libraries = loaded_libraries(binary);
    ASSERT_GT(libraries.size(), 5u) << binary;
    // One dpkg -S for all: with /usr merged, a library is registered under /lib or /usr/lib.
    std::string query = "dpkg -S";
    for (const std::string& path : libraries) {
      const std::string other = path.starts_with("/usr/") ? path.substr(4) : "/usr" + path;
      query += " '" + path + "' '" + other + "'";
    }
    std::istringstream lines(run_command(query).output);
    std::map<std::string, std::string> owner;  // path as registered -> package
    for (std::string line; std::getline(lines, line);) {
      const std::size_t colon_space = line.find(": /");
      if (colon_space == std::string::npos) continue;
      // "libfoo:amd64: /usr/lib/x86_64-linux-gnu/libfoo.so.1"
      const std::string package = line.substr(0, line.find(':'));
      const std::string path = line.substr(colon_space + 2);
      owner[path.starts_with("/usr/") ? path.substr(4) : path] = package;
    }
    for (const std::string& path : libraries) {
      const auto found = owner.find(path.starts_with("/usr/") ? path.substr(4) : path);
      ASSERT_NE(found, owner.end()) << path << " (loaded by " << binary << ") has no package";
      // A sanitized build's (make sanitize, make tsan) own runtime: the image builds Release.
      if (found->second.starts_with("libasan") || found->second.starts_with("libubsan") ||
          found->second.starts_with("libtsan"))
        continue;
      EXPECT_NE(runtime_packages.find(" " + found->second + " "), std::string::npos)
          << binary << " loads " << path << " of " << found->second
          << ", which the runtime stage does not install";
    }
  }
}

// Whether podman runs a container here: a one-file image (/bin/true and the two libraries it
// needs, from this machine) imported and run. Empty when it ran; otherwise podman's reason.
std::string podman_cannot_run(const fs::path& directory) {
  const std::string root = (directory / "root").string();
  const CommandResult run = run_command(
      "set -e; mkdir -p '" + root + "/bin' '" + root + "/lib64' '" + root +
      "/lib/x86_64-linux-gnu'; cp -L /usr/bin/true '" + root +
      "/bin/'; cp -L "
      "/lib/x86_64-linux-gnu/libc.so.6 '" +
      root +
      "/lib/x86_64-linux-gnu/'; cp -L "
      "/lib64/ld-linux-x86-64.so.2 '" +
      root + "/lib64/'; tar -C '" + root + "' -cf '" + (directory / "probe.tar").string() +
      "' .; timeout 120 podman import -q '" + (directory / "probe.tar").string() +
      "' localhost/sweepd-podman-probe >/dev/null; "
      "status=0; timeout 120 podman run --rm localhost/sweepd-podman-probe /bin/true || status=$?; "
      "podman rmi -f localhost/sweepd-podman-probe >/dev/null 2>&1 || true; exit $status");
  return run.exit_code == 0 ? "" : run.output + " (exit " + std::to_string(run.exit_code) + ")";
}

TEST_F(ContainerfileTest, PodmanCanRunTheImageHereOrSaysWhyNot) {
  if (!have_program("podman")) {
    GTEST_SKIP() << "podman is not installed, so the image is not built or run here; the "
                    "Containerfile is linted by the tests above instead";
  }
  const fs::path directory = fresh_directory("podman_probe");
  const std::string reason = podman_cannot_run(directory);
  fs::remove_all(directory);
  if (!reason.empty()) {
    GTEST_SKIP() << "podman cannot run a container on this machine, so the image is not "
                    "built or started here (the Containerfile is linted by the tests above). "
                    "podman said: "
                 << reason;
  }
  GTEST_SKIP() << "podman runs containers here; building the image (a full compile, about "
                  "15 minutes on 2 cores) is left to deploy/README.md's commands, not the suite";
}

}  // namespace
}  // namespace sweepd::test
