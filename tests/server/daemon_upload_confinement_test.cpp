// sweepd reads nothing for a client but what the client sent: an uploaded .gltf or .glb whose
// buffer URI names a file outside the store ("../x", "%2e%2e/x", an absolute path, file://) is
// refused with ModelLoadFailed naming the URI, in words that are the same whether that file
// exists or not and that give no server path, size or content; a --model-dir file may not reach
// out of its directory either. Two independent witnesses that the file is never opened:
//   - the canary is a FIFO nobody writes to (tests/io/fifo_canary.h): a daemon opening it for
//     reading would block there, and the watcher sees that reader however briefly it waits;
//   - under strace -f -e trace=%file (when strace is installed and may trace), no file system
//     call of the daemon (open, openat, stat, access, readlink, ...) names a canary at all.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <regex>

#include "tests/io/crafted_quad.h"
#include "tests/io/fifo_canary.h"
#include "tests/server/daemon_process.h"

namespace sweepd::test {
namespace {

using io::testing::FifoCanary;

constexpr const char* kCanary = "canary-never-opened";  // a FIFO outside store and model dir
constexpr const char* kSecret = "secret.txt";           // a file with a telling size and content
constexpr std::size_t kSecretBytes = 12345;

std::vector<std::uint8_t> as_bytes(const std::string& text) { return {text.begin(), text.end()}; }

// The crafted two-joint quad as .gltf text with its one buffer at `uri`.
std::string quad_gltf(const std::string& uri) {
  std::string unused;
  return io::testing::CraftedQuad().with_buffer_uri(uri, unused).dump();
}

// The same JSON as a .glb with no binary chunk: its buffer is the external `uri`.
std::vector<std::uint8_t> quad_glb(const std::string& uri) {
  std::string json = quad_gltf(uri);
  json.resize((json.size() + 3) / 4 * 4, ' ');  // chunks are 4-byte aligned, JSON padded with ' '
  const std::uint32_t header[5] = {0x46546C67u, 2u, static_cast<std::uint32_t>(20 + json.size()),
                                   static_cast<std::uint32_t>(json.size()), 0x4E4F534Au};
  std::vector<std::uint8_t> glb(sizeof(header) + json.size());
  std::memcpy(glb.data(), header, sizeof(header));
  std::memcpy(glb.data() + sizeof(header), json.data(), json.size());
  return glb;
}

// Sends LoadModel (an upload when `gltf` is not empty) and returns the Error's message, failing
// the test when the reply is not a ModelLoadFailed error.
std::string refusal_of(FrameClient& client, const std::string& name,
                       const std::vector<std::uint8_t>& gltf) {
  flatbuffers::FlatBufferBuilder builder;
  client.send_bytes(protocol::finish_message(
      builder,
      protocol::CreateLoadModelDirect(builder, name.c_str(), gltf.empty() ? nullptr : &gltf), 31));
  const protocol::Error* error = client.receive_as<protocol::Error>();
  if (error == nullptr) return {};
  EXPECT_EQ(error->code(), protocol::ErrorCode::ModelLoadFailed) << error->message()->str();
  return error->message()->str();
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// directory/ holds the canary FIFO, the secret, models/ (the --model-dir) and store/.
class UploadConfinement {
 public:
  explicit UploadConfinement(const std::string& name)
      : directory_(fresh_directory(name)), canary_(directory_ / kCanary) {
    fs::create_directories(directory_ / "models");
    std::ofstream(directory_ / kSecret) << std::string(kSecretBytes, 'q');
    std::ofstream(directory_ / "models" / "escape.gltf") << quad_gltf(std::string("../") + kCanary);
  }
  ~UploadConfinement() { fs::remove_all(directory_); }

  const fs::path& directory() const { return directory_; }
  std::vector<std::string> daemon_args() const {
    return {"--model-dir", (directory_ / "models").string(), "--position-maps", "0"};
  }

  // Every refusal the daemon must give, each checked while the canary watches.
  void expect_everything_refused(FrameClient& client) {
    ASSERT_TRUE(canary_.created());
    const std::string canary = (directory_ / kCanary).string();
    // upload URI -> as named in the error (tinygltf percent-decodes before anything else).
    // The store is directory/store, so "../" from there is directory/.
    const std::vector<std::pair<std::string, std::string>> uploads = {
        {std::string("../") + kCanary, std::string("../") + kCanary},
        {std::string("%2e%2e/") + kCanary, std::string("../") + kCanary},
        {canary, canary},
        {"file://" + canary, "file://" + canary},
    };
    int n = 0;
    for (const auto& [uri, named] : uploads) {
      for (const std::vector<std::uint8_t>& file : {as_bytes(quad_gltf(uri)), quad_glb(uri)}) {
        std::string message;
        EXPECT_FALSE(canary_.opened_during([&] {
          message = refusal_of(client, "escape_" + std::to_string(++n), file);
        })) << uri;
        EXPECT_TRUE(contains(message, "\"" + named + "\" refused")) << message;
        EXPECT_TRUE(contains(message, "self-contained")) << message;
        EXPECT_FALSE(contains(message, (directory_ / "store").string())) << message;
      }
    }
    // Existing or not, with a telling size or none, the words are the same.
    std::string secret = refusal_of(client, "secret", as_bytes(quad_gltf("../secret.txt")));
    const std::string absent = refusal_of(client, "secret", as_bytes(quad_gltf("../absent.txt")));
    EXPECT_FALSE(contains(secret, std::to_string(kSecretBytes))) << secret;
    EXPECT_FALSE(contains(secret, "qqqq")) << secret;
    secret.replace(secret.find("secret.txt"), 6, "absent");
    EXPECT_EQ(secret, absent);
    // A model-dir file reaching out of its directory.
    std::string message;
    EXPECT_FALSE(canary_.opened_during(
        [&] { message = refusal_of(client, "escape.gltf", std::vector<std::uint8_t>{}); }));
    EXPECT_TRUE(contains(message, std::string("\"../") + kCanary + "\" refused")) << message;
  }

 private:
  fs::path directory_;
  FifoCanary canary_;
};

TEST(DaemonUploadConfinement, UrisOutsideAreRefusedWithoutOpeningTheFile) {
  UploadConfinement scene("upload_confinement");
  DaemonProcess daemon(scene.directory(), scene.daemon_args());
  ASSERT_TRUE(daemon.running()) << daemon.log();
  FrameClient client(daemon.port());
  ASSERT_NE(client.hello(""), nullptr);
  scene.expect_everything_refused(client);
}

// The strace binary, when it is installed and may trace a child here (no seccomp or Yama rule
// against ptrace); empty otherwise.
std::string usable_strace() {
  FILE* pipe = popen("command -v strace", "r");
  if (!pipe) return {};
  char path[4096] = {};
  const bool found = std::fgets(path, sizeof(path), pipe) != nullptr;
  pclose(pipe);
  if (!found) return {};
  std::string strace(path);
  strace.erase(strace.find_last_not_of("\n") + 1);
  const std::string probe = strace + " -D -f -o /dev/null true >/dev/null 2>&1";
  return std::system(probe.c_str()) == 0 ? strace : std::string();
}

TEST(DaemonUploadConfinement, UnderStraceNoFileCallNamesACanary) {
  const std::string strace = usable_strace();
  if (strace.empty()) GTEST_SKIP() << "strace is not installed or may not trace here";
  UploadConfinement scene("upload_confinement_strace");
  const fs::path trace = scene.directory() / "trace.txt";
  // -D: strace runs as a detached grandchild, so the child DaemonProcess signals and waits for
  // is sweepd itself; -f follows its threads. Under `make sanitize` the traced daemon must not
  // run LeakSanitizer, which cannot work under ptrace (env execs strace in place).
  const char* asan_options = std::getenv("ASAN_OPTIONS");
  const std::string no_leak_check =
      "ASAN_OPTIONS=" + std::string(asan_options ? asan_options : "") + ":detect_leaks=0";
  DaemonProcess daemon(scene.directory(), scene.daemon_args(),
                       {"/usr/bin/env", no_leak_check, strace, "-D", "-f", "-e", "trace=%file",
                        "-o", trace.string(), "--"});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  const pid_t pid = daemon.pid();
  {
    FrameClient client(daemon.port());
    ASSERT_NE(client.hello(""), nullptr);
    scene.expect_everything_refused(client);
  }
  daemon.signal(SIGTERM);
  ASSERT_EQ(daemon.wait(), 0) << daemon.log();
  // strace writes the daemon's exit last ("<pid>  +++ exited with 0 +++"); wait for it so the
  // trace is whole.
  const std::regex exited("(^|\n)" + std::to_string(pid) + " +\\+\\+\\+ exited with");
  std::string text;
  for (int i = 0; i < 1000 && !std::regex_search(text, exited); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    text = read_text(trace);
  }
  ASSERT_TRUE(std::regex_search(text, exited))
      << "the trace did not end:\n"
      << text.substr(text.size() - std::min<std::size_t>(text.size(), 3000));
  // The trace saw the daemon's file calls (the uploads it wrote to its store as <content
  // id>.glb, the model-dir file it read), and none of them named the canary or the secret.
  EXPECT_TRUE(std::regex_search(text, std::regex("store/[0-9a-f]{64}\\.glb")))
      << text.substr(0, 2000);
  EXPECT_TRUE(contains(text, "models/escape.gltf")) << text.substr(0, 2000);
  EXPECT_FALSE(contains(text, kCanary));
  EXPECT_FALSE(contains(text, kSecret));
}

}  // namespace
}  // namespace sweepd::test
