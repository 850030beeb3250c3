// Which files a glTF's external URIs may name: resolve_external_uri on its own (relative paths
// inside the directory pass; `..`, absolute paths, schemes, control characters and symlinks
// leading out are refused), then load_gltf under each policy, with a FIFO canary outside the
// model directory that proves the refused files are never opened (tests/io/fifo_canary.h).
#include "io/gltf/gltf_uri_policy.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <functional>
#include <string>
#include <vector>

#include "io/gltf/gltf_load.h"
#include "io/gltf/gltf_save.h"
#include "mannequin/mannequin.h"
#include "tests/io/crafted_quad.h"
#include "tests/io/fifo_canary.h"
#include "tests/io/gltf_test_files.h"

namespace sweepd::io {
namespace {

namespace fs = std::filesystem;
using testing::CraftedQuad;
using testing::FifoCanary;
using testing::json;
using testing::ScratchDirectory;

// scratch/models is the directory models are loaded from; scratch itself is "outside".
class UriScratch {
 public:
  UriScratch() : models_(dir_ / "models") { fs::create_directories(models_); }
  fs::path outside(const std::string& name) const { return dir_ / name; }
  fs::path models(const std::string& name = "") const {
    return name.empty() ? models_ : models_ / name;
  }
  GltfUriPolicy within_models() const { return GltfUriPolicy::within(models_); }

 private:
  ScratchDirectory dir_;
  fs::path models_;
};

// The message of the LoadError `load` throws; fails the test when it throws none.
std::string load_error_of(const std::function<void()>& load) {
  try {
    load();
  } catch (const LoadError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no LoadError";
  return {};
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(GltfUriPolicy, SelfContainedRefusesEveryExternalUri) {
  for (const std::string uri : {"model.bin", "sub/model.bin", "../x.bin", "/etc/passwd"}) {
    const UriResolution resolution = resolve_external_uri(GltfUriPolicy::self_contained(), uri);
    EXPECT_TRUE(resolution.file.empty()) << uri;
    EXPECT_TRUE(contains(resolution.refusal, "self-contained")) << resolution.refusal;
  }
}

TEST(GltfUriPolicy, RelativePathsInsideTheDirectoryResolveToTheirCanonicalFile) {
  UriScratch scratch;
  fs::create_directories(scratch.models("sub"));
  testing::write_bytes(scratch.models("a.bin"), "a");
  testing::write_bytes(scratch.models("sub/b.bin"), "b");
  const fs::path root = fs::canonical(scratch.models());
  const std::vector<std::pair<std::string, fs::path>> cases = {
      {"a.bin", root / "a.bin"},
      {"./a.bin", root / "a.bin"},
      {"sub/../a.bin", root / "a.bin"},  // `..` that stays inside is fine
      {"sub/b.bin", root / "sub" / "b.bin"},
      {"sub/c:d.bin", root / "sub" / "c:d.bin"},  // a ':' after a '/' is no scheme
      {"missing.bin", root / "missing.bin"},      // allowed; then simply not found
  };
  for (const auto& [uri, expected] : cases) {
    const UriResolution resolution = resolve_external_uri(scratch.within_models(), uri);
    EXPECT_EQ(resolution.file, expected) << uri << ": " << resolution.refusal;
    EXPECT_TRUE(resolution.refusal.empty()) << uri;
  }
}

TEST(GltfUriPolicy, EscapesAbsolutePathsSchemesAndControlCharactersAreRefused) {
  UriScratch scratch;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"../outside.bin", ".."},
      {"sub/../../outside.bin", ".."},
      {"..", ".."},
      {"/etc/passwd", "absolute"},
      {"//etc/passwd", "absolute"},
      {"file:///etc/passwd", "scheme"},
      {"file:outside.bin", "scheme"},
      {"FILE:/etc/passwd", "scheme"},
      {"http://example.com/x.bin", "scheme"},
      {"C:/Windows/x.bin", "scheme"},
      {std::string("a.bin\0/../../x", 14), "control"},  // NUL would cut the opened path short
      {"a\nb.bin", "control"},
      {"", "no file"},
  };
  for (const auto& [uri, keyword] : cases) {
    const UriResolution resolution = resolve_external_uri(scratch.within_models(), uri);
    EXPECT_TRUE(resolution.file.empty()) << uri;
    EXPECT_TRUE(contains(resolution.refusal, keyword)) << uri << ": " << resolution.refusal;
    EXPECT_FALSE(contains(resolution.refusal, scratch.models().string())) << resolution.refusal;
  }
}

TEST(GltfUriPolicy, SymlinksLeadingOutAreRefusedAndThoseStayingInsideFollowed) {
  UriScratch scratch;
  fs::create_directories(scratch.outside("elsewhere"));
  fs::create_directories(scratch.models("sub"));
  testing::write_bytes(scratch.outside("elsewhere/secret.bin"), "s");
  testing::write_bytes(scratch.models("sub/b.bin"), "b");
  fs::create_directory_symlink("../elsewhere", scratch.models("link_out"));
  fs::create_symlink("../elsewhere/secret.bin", scratch.models("file_out.bin"));
  fs::create_directory_symlink("sub", scratch.models("alias"));
  for (const std::string uri : {"link_out/secret.bin", "file_out.bin", "link_out/absent.bin"}) {
    const UriResolution resolution = resolve_external_uri(scratch.within_models(), uri);
    EXPECT_TRUE(resolution.file.empty()) << uri;
    EXPECT_TRUE(contains(resolution.refusal, "symlink")) << uri << ": " << resolution.refusal;
  }
  EXPECT_EQ(resolve_external_uri(scratch.within_models(), "alias/b.bin").file,
            fs::canonical(scratch.models("sub/b.bin")));
}

TEST(GltfUriPolicy, ASiblingWhoseNameStartsLikeTheRootIsOutside) {
  // A string-prefix check would take <scratch>/models-old/x.bin for a file in <scratch>/models.
  UriScratch scratch;
  fs::create_directories(scratch.outside("models-old"));
  testing::write_bytes(scratch.outside("models-old/x.bin"), "x");
  fs::create_directory_symlink("../models-old", scratch.models("old"));
  const UriResolution resolution = resolve_external_uri(scratch.within_models(), "old/x.bin");
  EXPECT_TRUE(resolution.file.empty());
  EXPECT_TRUE(contains(resolution.refusal, "outside")) << resolution.refusal;
}

// The crafted quad in models/crafted.gltf with its buffer at `uri`; the buffer's bytes are
// written to models/<bin_name> when bin_name is given.
fs::path write_quad(const UriScratch& scratch, const std::string& uri,
                    const std::string& bin_name = "") {
  std::string bin;
  const json gltf = CraftedQuad().with_buffer_uri(uri, bin);
  if (!bin_name.empty()) {
    fs::create_directories(scratch.models(bin_name).parent_path());
    testing::write_bytes(scratch.models(bin_name), bin);
  }
  const fs::path file = scratch.models("crafted.gltf");
  testing::write_bytes(file, gltf.dump());
  return file;
}

TEST(GltfExternalUris, ExternalBinsInsideTheDirectoryLoadAsTheEmbeddedOne) {
  UriScratch scratch;
  testing::write_bytes(scratch.models("embedded.gltf"), CraftedQuad().to_json().dump());
  const deform::Model embedded = load_gltf(scratch.models("embedded.gltf"));
  // tinygltf percent-decodes before it opens: "sub%20dir" is the folder "sub dir".
  for (const auto& [uri, bin_name] : std::vector<std::pair<std::string, std::string>>{
           {"quad.bin", "quad.bin"}, {"sub%20dir/quad.bin", "sub dir/quad.bin"}}) {
    const fs::path file = write_quad(scratch, uri, bin_name);
    for (const deform::Model& model : {load_gltf(file), load_gltf(file, scratch.within_models())}) {
      // Same bytes through the same arithmetic: exactly equal.
      EXPECT_EQ(model.positions, embedded.positions) << uri;
      EXPECT_EQ(model.skin_weights, embedded.skin_weights) << uri;
    }
  }
}

TEST(GltfExternalUris, SelfContainedLoadsDataUrisAndGlbChunks) {
  UriScratch scratch;
  testing::write_bytes(scratch.models("embedded.gltf"), CraftedQuad().to_json().dump());
  EXPECT_EQ(
      load_gltf(scratch.models("embedded.gltf"), GltfUriPolicy::self_contained()).vertex_count(),
      4u);
  const deform::Model mannequin = mannequin::make_mannequin({.target_vertices = 3000});
  save_gltf(mannequin, scratch.models("mannequin.glb"));
  EXPECT_EQ(
      load_gltf(scratch.models("mannequin.glb"), GltfUriPolicy::self_contained()).vertex_count(),
      mannequin.vertex_count());
}

TEST(GltfExternalUris, SelfContainedRefusesEvenABinBesideTheFile) {
  UriScratch scratch;
  const fs::path file = write_quad(scratch, "quad.bin", "quad.bin");
  const std::string message =
      load_error_of([&] { load_gltf(file, GltfUriPolicy::self_contained()); });
  EXPECT_TRUE(contains(message, "\"quad.bin\" refused")) << message;
  EXPECT_TRUE(contains(message, "self-contained")) << message;
}

TEST(GltfExternalUris, RefusedUrisNeverOpenTheFileTheyName) {
  UriScratch scratch;
  FifoCanary canary(scratch.outside("canary"));
  ASSERT_TRUE(canary.created());
  const std::string absolute = canary.path().string();
  fs::create_directories(scratch.models("sub"));
  fs::create_symlink("../canary", scratch.models("escape.bin"));
  fs::create_directory_symlink("..", scratch.models("up"));
  // uri as written -> as tinygltf decodes it (and as the error names it)
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"../canary", "../canary"},
      {"sub/../../canary", "sub/../../canary"},
      {"%2e%2e/canary", "../canary"},
      {"%2E%2E%2Fcanary", "../canary"},
      {absolute, absolute},
      {"file://" + absolute, "file://" + absolute},
      {"file:../canary", "file:../canary"},
      {"escape.bin", "escape.bin"},
      {"up/canary", "up/canary"},
  };
  for (const auto& [uri, decoded] : cases) {
    const fs::path file = write_quad(scratch, uri);
    for (const GltfUriPolicy& policy : {GltfUriPolicy::self_contained(), scratch.within_models()}) {
      std::string message;
      EXPECT_FALSE(canary.opened_during([&] {
        message = load_error_of([&] { load_gltf(file, policy); });
      })) << uri;
      EXPECT_TRUE(contains(message, "\"" + decoded + "\" refused")) << uri << ": " << message;
    }
    EXPECT_FALSE(canary.opened_during([&] { load_error_of([&] { load_gltf(file); }); })) << uri;
  }
}

TEST(GltfExternalUris, ARefusalSaysNothingAboutTheFileItNames) {
  // The same words whether the named file exists (with a telling size) or not.
  UriScratch scratch;
  testing::write_bytes(scratch.outside("secret.txt"), std::string(12345, 's'));
  for (const GltfUriPolicy& policy : {GltfUriPolicy::self_contained(), scratch.within_models()}) {
    std::string present =
        load_error_of([&] { load_gltf(write_quad(scratch, "../secret.txt"), policy); });
    const std::string absent =
        load_error_of([&] { load_gltf(write_quad(scratch, "../absent.txt"), policy); });
    EXPECT_FALSE(contains(present, "12345")) << present;
    present.replace(present.find("secret"), 6, "absent");
    EXPECT_EQ(present, absent);
  }
}

TEST(GltfExternalUris, ARefusedUriIsQuotedOnOneBoundedLine) {
  // A stranger's URI: at most 200 of its bytes are shown, control characters and quotes escaped.
  UriScratch scratch;
  const std::string long_uri = "../" + std::string(10000, 'a');
  const std::string message = load_error_of(
      [&] { load_gltf(write_quad(scratch, long_uri), GltfUriPolicy::self_contained()); });
  EXPECT_LT(message.size(), 200u + 300u) << message;  // 300: the file name and the reason
  EXPECT_TRUE(contains(message, "aaa...\" refused")) << message;
  const std::string odd = load_error_of(
      [&] { load_gltf(write_quad(scratch, "a\nb\"c"), GltfUriPolicy::self_contained()); });
  EXPECT_TRUE(contains(odd, R"("a\x0ab\"c" refused)")) << odd;
}

TEST(GltfExternalUris, ImageUrisAreRefusedLikeBufferUris) {
  UriScratch scratch;
  FifoCanary canary(scratch.outside("canary.png"));
  ASSERT_TRUE(canary.created());
  json gltf = CraftedQuad().to_json();
  gltf["images"] = {{{"uri", "../canary.png"}}};
  testing::write_bytes(scratch.models("textured.gltf"), gltf.dump());
  for (const GltfUriPolicy& policy : {GltfUriPolicy::self_contained(), scratch.within_models()}) {
    std::string message;
    EXPECT_FALSE(canary.opened_during([&] {
      message = load_error_of([&] { load_gltf(scratch.models("textured.gltf"), policy); });
    }));
    EXPECT_TRUE(contains(message, "\"../canary.png\" refused")) << message;
  }
  // An image inside the directory is allowed (read, never decoded: textures play no part).
  gltf["images"] = {{{"uri", "skin.png"}}};
  testing::write_bytes(scratch.models("skin.png"), "not decoded");
  testing::write_bytes(scratch.models("textured.gltf"), gltf.dump());
  EXPECT_EQ(load_gltf(scratch.models("textured.gltf")).vertex_count(), 4u);
}

TEST(GltfExternalUris, NoSecondLookInTheWorkingDirectory) {
  // tinygltf alone tries ./<uri> when <base_dir>/<uri> is missing.
  UriScratch scratch;
  fs::create_directories(scratch.outside("cwd"));
  FifoCanary canary(scratch.outside("cwd/quad.bin"));
  ASSERT_TRUE(canary.created());
  const fs::path file = write_quad(scratch, "quad.bin");  // no models/quad.bin
  const fs::path previous = fs::current_path();
  fs::current_path(scratch.outside("cwd"));
  std::string message;
  const bool opened =
      canary.opened_during([&] { message = load_error_of([&] { load_gltf(file); }); });
  fs::current_path(previous);
  EXPECT_FALSE(opened);
  EXPECT_TRUE(contains(message, "quad.bin")) << message;
}

}  // namespace
}  // namespace sweepd::io
