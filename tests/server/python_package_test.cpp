// client_examples/python as a user gets it: `pip install` into a fresh venv, offline (no
// index, no build isolation; Debian's numpy, flatbuffers and setuptools through
// --system-site-packages), then tests/server/python_package_check.py drives a real daemon with
// the installed package only (glTF animation clips included, made here with
// tests/io/baked_gltf_clip.h). Its posed vertices must equal the library's DeformJob for the
// same bound model. The package's committed protocol code must be what flatc makes of the
// schema today.
#include <gtest/gtest.h>

#include <cstring>

#include "io/gltf/gltf_save.h"
#include "io/sweepbind/sweepbind.h"
#include "mannequin/mannequin.h"
#include "selfcheck/binding_self_check.h"
#include "tests/deploy/shell_command.h"
#include "tests/io/baked_gltf_clip.h"
#include "tests/server/daemon_process.h"
#include "tests/server/pose_frames.h"
#include "tests/server/stored_binding.h"

namespace sweepd::test::python_package_test {
namespace {

const fs::path kPackage = fs::path(SWEEPD_SOURCE_DIR) / "client_examples/python";
const fs::path kClip = fs::path(SWEEPD_SHARED_DATA) / "motion/cmu_01_01.bvh";

std::string quoted(const fs::path& path) { return "'" + path.string() + "'"; }

TEST(PythonPackage, CommittedProtocolCodeIsWhatFlatcMakesOfTheSchema) {
  const ScratchDirectory directory("python_package_flatc");
  const CommandResult flatc =
      run_command(std::string(SWEEPD_FLATC) + " --python -o " + quoted(directory) + " " +
                  quoted(fs::path(SWEEPD_SOURCE_DIR) / "protocol/sweepd.fbs"));
  ASSERT_EQ(flatc.exit_code, 0) << flatc.output;
  std::size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(directory / "sweepd")) {
    if (!entry.is_regular_file()) continue;
    const fs::path relative = fs::relative(entry.path(), directory);
    EXPECT_EQ(read_text(kPackage / relative), read_text(entry.path()))
        << relative << " differs from flatc's; regenerate: flatc --python -o " << kPackage
        << " protocol/sweepd.fbs";
    ++files;
  }
  std::size_t committed = 0;
  for (const auto& entry : fs::recursive_directory_iterator(kPackage / "sweepd")) {
    committed += entry.is_regular_file() && entry.path().extension() == ".py";
  }
  EXPECT_EQ(committed, files) << "the package holds files flatc no longer makes";
  EXPECT_GT(files, 30u);  // one module per schema type
}

TEST(PythonPackage, InstallsOfflineIntoAVenvAndPosesLikeTheLibrary) {
  ASSERT_TRUE(fs::exists(kClip)) << kClip << ": the shared data must sit beside the checkout";
  const ScratchDirectory directory("python_package");
  const fs::path venv = directory / "venv";
  const CommandResult create =
      run_command("/usr/bin/python3 -m venv --system-site-packages " + quoted(venv));
  ASSERT_EQ(create.exit_code, 0) << create.output;
  // pip builds in a copy of the package (its own build/ and egg-info stay out of the tree),
  // without a build/ that an earlier install from the tree left: setuptools would reuse it.
  const fs::path source = directory / "source";
  fs::copy(kPackage, source, fs::copy_options::recursive);
  fs::remove_all(source / "build");
  const CommandResult install = run_command(
      quoted(venv / "bin/pip") + " install --no-index --no-build-isolation " + quoted(source));
  ASSERT_EQ(install.exit_code, 0) << install.output;
  fs::remove_all(source);

  const fs::path glb = directory / "body.glb";
  const deform::Model body = mannequin::make_mannequin({.target_vertices = 2500});
  io::save_gltf(body, glb);
  // The body with three animations of its own joints (cmu_01_01 baked at 6 keys).
  const fs::path animated = directory / "animated.glb";
  io::testing::write_baked_gltf(body, io::testing::bake_cmu_clip(body, 6), animated);
  const fs::path unix_socket = directory / "sweepd.sock";
  DaemonProcess daemon(directory, {"--token", "t0k", "--mannequin-vertices", "1000",
                                   "--unix-socket", unix_socket.string(), "--vmc-listen",
                                   "127.0.0.1:0", "--vmc-port-file",
                                   (directory / "vmc_port").string()});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  // A second server with a store of its own: the package must upload to it again.
  fs::create_directories(directory / "other");
  DaemonProcess other(directory / "other", {"--token", "t0k", "--mannequin-vertices", "1000"});
  ASSERT_TRUE(other.running()) << other.log();
  const std::size_t joints = body.skeleton.joints.size();
  const std::vector<glm::quat> rotations = bent_rotations(joints);
  const std::vector<protocol::Quat> wire = to_wire(rotations);
  {
    std::ofstream out(directory / "rotations.f32", std::ios::binary);
    out.write(reinterpret_cast<const char*>(wire.data()),
              static_cast<std::streamsize>(wire.size() * sizeof(protocol::Quat)));
  }

  // Run from the directory, not the source tree: only the installed package can be imported.
  const CommandResult check =
      run_command("cd " + quoted(directory) + " && " + quoted(venv / "bin/python") + " " +
                  quoted(fs::path(SWEEPD_SOURCE_DIR) / "tests/server/python_package_check.py") +
                  " " + std::to_string(daemon.port()) + " t0k " + quoted(glb) + " " +
                  quoted(directory / "rotations.f32") + " " + quoted(directory) + " " +
                  std::to_string(other.port()) + " " + quoted(kClip) + " " + quoted(animated) +
                  " " + quoted(unix_socket) + " " +
                  std::to_string(std::stoi(read_text(directory / "vmc_port"))));
  ASSERT_EQ(check.exit_code, 0) << check.output << daemon.log();
  EXPECT_NE(check.output.find("ok"), std::string::npos) << check.output;

  // The library's own deformation of the model as the daemon bound it.
  const deform::BoundModel bound =
      io::load_sweepbind(stored_binding(directory / "store", "uploaded"));
  const Deformed library = library_deformation(bound, rotations, deform::DeformMethod::kSweep);
  const std::vector<std::uint8_t> bytes = read_bytes(directory / "positions.f32");
  ASSERT_EQ(bytes.size(), library.positions.size() * sizeof(glm::vec3));
  std::vector<glm::vec3> served(library.positions.size());
  std::memcpy(served.data(), bytes.data(), bytes.size());
  float largest = 0.0f, moved = 0.0f;
  for (std::size_t v = 0; v < served.size(); ++v) {
    largest = std::max(largest, glm::length(served[v] - library.positions[v]));
    moved = std::max(moved, glm::length(served[v] - bound.model.positions[v]));
  }
  // The acceptance's 1e-6 m: float32 on the wire, the same DeformJob on both sides.
  EXPECT_LE(largest, 1e-6f);
  EXPECT_GT(moved, 0.05f);  // the pose bent the body: the comparison is not of rest poses

  // (1.14) Model.bind_warnings: the library's self-check of the stored binding, word for word
  // (the same deterministic check on the same binding).
  std::string expected_warnings;
  for (const std::string& warning : selfcheck::self_check_warnings(
           selfcheck::check_binding(bound, selfcheck::range_of_motion_peaks(bound))))
    expected_warnings += warning + "\n";
  EXPECT_EQ(read_text(directory / "bind_warnings.txt"), expected_warnings);

  const std::vector<std::uint8_t> exr = read_bytes(directory / "map.exr");
  ASSERT_GE(exr.size(), 4u);
  EXPECT_EQ(std::memcmp(exr.data(), "\x76\x2f\x31\x01", 4), 0) << "not an OpenEXR file";

  // The package's contact sheet (protocol 1.11) is `sweepctl sheet`'s of the same body and clip
  // byte for byte: the daemon draws it with the command's code on the same renderer.
  const CommandResult local = run_command(
      quoted(fs::path(SWEEPD_SWEEPCTL)) + " sheet " + quoted(glb) + " --bvh " + quoted(kClip) +
      " --frames 100,300 --methods sweep,lbs --cell 64x96 --focus elbow_l --heat stretch -o " +
      quoted(directory / "local_sheet.png"));
  ASSERT_EQ(local.exit_code, 0) << local.output;
  const std::vector<std::uint8_t> sheet = read_bytes(directory / "sheet.png");
  EXPECT_GT(sheet.size(), 1000u);
  EXPECT_TRUE(sheet == read_bytes(directory / "local_sheet.png"))
      << "the package's sheet differs from sweepctl's";
}

}  // namespace
}  // namespace sweepd::test::python_package_test
