// sweepctl sheet as a user runs it: the shared male and CMU clip 01_01 in small cells (64-128
// pixels wide, so a run takes about a second on llvmpipe), the PNG read back and checked cell by
// cell; --video through ffmpeg, or its clear refusal when ffmpeg is absent; frames past the clip
// refused (the command line's refusals are in sweepctl_test.cpp).
#include <gtest/gtest.h>
#include <stb/stb_image.h>  // implemented in Debian's libstb

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/cli/sweepctl_process.h"

namespace {

namespace fs = std::filesystem;

using Result = sweepd::test::SweepctlResult;
using sweepd::test::run_sweepctl;
using sweepd::test::shared;

struct Picture {
  int width = 0, height = 0;
  std::vector<unsigned char> rgba;
  const unsigned char* pixel(int x, int y) const { return &rgba[(std::size_t(y) * width + x) * 4]; }
};

Picture read_png(const fs::path& file) {
  Picture picture;
  int channels = 0;
  stbi_uc* pixels = stbi_load(file.c_str(), &picture.width, &picture.height, &channels, 4);
  if (pixels == nullptr) return picture;
  picture.rgba.assign(pixels, pixels + std::size_t(picture.width) * picture.height * 4);
  stbi_image_free(pixels);
  return picture;
}

// The caption band's height and ink at cells narrower than 400 pixels
// (gpu/sheet/contact_sheet.cpp).
constexpr int kCaptionHeight = 26;
constexpr std::array<int, 3> kInk{30, 30, 36};
// gpu::PreviewOptions' default background, 0.9, 0.9, 0.92 of 255.
constexpr std::array<int, 3> kBackground{230, 230, 235};

bool near(const unsigned char* p, const std::array<int, 3>& colour, int tolerance) {
  for (int c = 0; c < 3; ++c)
    if (std::abs(p[c] - colour[c]) > tolerance) return false;
  return true;
}

struct Cell {
  int ink = 0;            // caption pixels in the ink colour
  double coverage = 0.0;  // render pixels that are not background
  int blue = 0;           // render pixels where blue leads red by 40 (the heat map's cold end)
};

Cell measure_cell(const Picture& sheet, int column, int row, int cell_width, int cell_height) {
  Cell cell;
  const int left = column * cell_width, top = row * cell_height;
  int covered = 0, total = 0;
  for (int y = top; y < top + cell_height; ++y)
    for (int x = left; x < left + cell_width; ++x) {
      const unsigned char* p = sheet.pixel(x, y);
      if (y < top + kCaptionHeight) {
        cell.ink += near(p, kInk, 0);
        continue;
      }
      ++total;
      // 6 of 255: MSAA edges blend towards the background; a covered pixel is far darker.
      covered += !near(p, kBackground, 6);
      cell.blue += p[2] > p[0] + 40;
    }
  cell.coverage = double(covered) / total;
  return cell;
}

// Mean absolute channel difference between two cells' renders.
double cell_difference(const Picture& sheet, int a, int b, int cell_width, int cell_height) {
  double sum = 0.0;
  int count = 0;
  for (int y = kCaptionHeight; y < cell_height; ++y)
    for (int x = 0; x < cell_width; ++x)
      for (int c = 0; c < 3; ++c, ++count)
        sum +=
            std::abs(sheet.pixel(a * cell_width + x, y)[c] - sheet.pixel(b * cell_width + x, y)[c]);
  return sum / count;
}

class SweepctlSheet : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(male_) || !fs::exists(clip_)) GTEST_SKIP() << "shared data absent";
    dir_ = sweepd::test::process_scratch("sweepctl_sheet_test");
  }
  std::string model_and_clip() const { return male_.string() + " --bvh " + clip_.string(); }

  fs::path male_ = shared("models/makehuman_male_cmu.glb");
  fs::path clip_ = shared("motion/cmu_01_01.bvh");
  fs::path dir_;
};

TEST_F(SweepctlSheet, GridHasACaptionedBodyInEveryCell) {
  const fs::path png = dir_ / "sheet.png";
  const Result r =
      run_sweepctl("sheet " + model_and_clip() +
                   " --frames 197,1257 --methods sweep,lbs,dqs --cell 96x128 -o " + png.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("2 frames x 3 methods"), std::string::npos) << r.output;
  const Picture sheet = read_png(png);
  // rows × columns cells of 96×128 exactly.
  ASSERT_EQ(sheet.width, 3 * 96);
  ASSERT_EQ(sheet.height, 2 * 128);
  for (int row = 0; row < 2; ++row)
    for (int column = 0; column < 3; ++column) {
      const Cell cell = measure_cell(sheet, column, row, 96, 128);
      // A captioned cell has ink in its band: two lines of 5×7 glyphs (measured 151-185 pixels).
      EXPECT_GT(cell.ink, 100) << "row " << row << " column " << column;
      // The whole body, framed to the same scale in every cell, covers 8-40 % of the render
      // (measured 14-16 %: a body is tall and thin, and the crouch of frame 197 shares the scale).
      EXPECT_GT(cell.coverage, 0.08) << "row " << row << " column " << column;
      EXPECT_LT(cell.coverage, 0.40) << "row " << row << " column " << column;
      EXPECT_EQ(cell.blue, 0) << "no heat map asked";
    }
}

TEST_F(SweepctlSheet, SweepDiffersFromLbsAtABentElbowAndHeatColoursTheSkin) {
  // Frame 1257: both elbows bent furthest in the clip. A column given twice renders the same
  // pixels (the control); sweep and LBS differ there.
  const fs::path png = dir_ / "elbow.png";
  Result r = run_sweepctl(
      "sheet " + model_and_clip() +
      " --frames 1257 --methods sweep,lbs,sweep --focus elbow_l --cell 96x128 -o " + png.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  Picture sheet = read_png(png);
  ASSERT_EQ(sheet.width, 3 * 96);
  ASSERT_EQ(sheet.height, 128);
  // A close-up fills far more of its cell than the whole body does (measured 41 % against 16 %).
  EXPECT_GT(measure_cell(sheet, 0, 0, 96, 128).coverage, 0.3);
  EXPECT_EQ(cell_difference(sheet, 0, 2, 96, 128), 0.0);
  // Measured 5.2 (of 255, mean over the render): the two methods put the bent elbow's skin in
  // different places; 2 is well above the difference of one method rendered twice (0).
  EXPECT_GT(cell_difference(sheet, 0, 1, 96, 128), 2.0);

  r = run_sweepctl("sheet " + model_and_clip() +
                   " --frames 1257 --methods lbs --focus elbow_l --heat stretch --cell 96x128 -o " +
                   png.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  sheet = read_png(png);
  // The heat map's cold end (little stretch: most of the arm) is blue, which the skin never is
  // (measured 1349 of the render's 9792 pixels).
  EXPECT_GT(measure_cell(sheet, 0, 0, 96, 128).blue, 500);
}

TEST_F(SweepctlSheet, VideoThroughFfmpegOrAClearRefusalWithoutIt) {
  const fs::path mp4 = dir_ / "clip.mp4";
  const std::string arguments =
      "sheet " + model_and_clip() + " --frames 600-602 --cell 64x96 --video " + mp4.string();
  // Without ffmpeg on PATH (sweepctl itself is named by its full path): refused, naming it.
  Result r = run_sweepctl(arguments, "2>&1", "PATH=/nonexistent ");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("--video needs ffmpeg, which is not on PATH"), std::string::npos)
      << r.output;
  if (std::system("command -v ffmpeg >/dev/null") != 0)
    GTEST_SKIP() << "ffmpeg absent (deploy/install-deps.sh installs it)";
  r = run_sweepctl(arguments);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("3 frames at 30 fps, 3 methods side by side"), std::string::npos)
      << r.output;
  // An MP4 starts with its ftyp box: a 4-byte size, then "ftyp".
  std::ifstream file(mp4, std::ios::binary);
  char head[8] = {};
  file.read(head, 8);
  EXPECT_EQ(std::string(head + 4, 4), "ftyp");
}

TEST_F(SweepctlSheet, FramesPastTheClipAreRefusedNamingThem) {
  const Result r = run_sweepctl("sheet " + model_and_clip() + " --frames 5,99999 -o " +
                                (dir_ / "x.png").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("frame 99999 does not exist"), std::string::npos) << r.output;
}

}  // namespace
