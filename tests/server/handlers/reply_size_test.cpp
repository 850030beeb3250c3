// Reply size of a contact sheet (reply_size.h): the bound holds for the least compressible
// picture there is, random bytes (stb_image_write's deflate cannot shrink them), and is not
// loose by more than the 9-bits-a-byte worst case it assumes; and work_size.h reserves more
// than the reply for it.
#include "server/handlers/reply_size.h"

#include <gtest/gtest.h>

#include <random>

#include "io/png/png_write.h"
#include "server/handlers/work_size.h"

namespace sweepd::server {
namespace {

TEST(ReplySize, ASheetOfRandomPixelsEncodesWithinItsBound) {
  sheet::SheetOptions options;
  options.methods = {deform::methods_by_name().at("sweep"), deform::methods_by_name().at("lbs")};
  options.frames = {0, 5};
  options.cell_width = 160;
  options.cell_height = 96;
  const int width = 2 * 160, height = 2 * 96;
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width) * height * 4);
  std::mt19937 random(49);
  for (std::uint8_t& byte : rgba) byte = static_cast<std::uint8_t>(random());
  std::vector<std::uint8_t> png;
  io::encode_png(width, height, rgba, png);
  const std::uint64_t bound = largest_sheet_reply_bytes(options);
  EXPECT_LE(png.size(), bound);
  // The bound is the filtered rows' 9/8 and 3 KiB of fields: within 15 % of random bytes' PNG.
  EXPECT_LE(bound, png.size() * 115 / 100) << png.size();
  EXPECT_GT(sheet_work_bytes(options), 5 * bound);
}

TEST(ReplySize, ASheetPastTheFrameLimitNamesTheLargestCellThatFits) {
  sheet::SheetOptions options;
  options.methods = {deform::methods_by_name().at("sweep")};
  options.frames = {0};
  options.cell_width = 2048;
  options.cell_height = 2048;
  const std::optional<RequestError> error = check_sheet_fits(options, 4u << 20);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->code, protocol::ErrorCode::InvalidArgument);
  // 4 MiB: 965 x 965 cells at 9/8 of 4 bytes a pixel and a filter byte a row, with 3 KiB.
  EXPECT_NE(error->message.find("ask for smaller cells (9"), std::string::npos) << error->message;
  unsigned side = 0;
  ASSERT_EQ(std::sscanf(error->message.c_str() + error->message.find("cells (") + 7, "%u", &side), 1);
  options.cell_width = options.cell_height = static_cast<int>(side);
  EXPECT_FALSE(check_sheet_fits(options, 4u << 20).has_value()) << side;
  options.cell_width = options.cell_height = static_cast<int>(side * 102 / 100);
  EXPECT_TRUE(check_sheet_fits(options, 4u << 20).has_value()) << side;  // no much larger fits
}

}  // namespace
}  // namespace sweepd::server
