// sweepctl sheet: a contact sheet — a PNG grid of shaded renders, one row per clip frame and one
// column per deformation method, each cell captioned with the method, the frame and the worst
// edge stretch — and with --video a side-by-side .mp4 of the methods over the frames (Debian's
// ffmpeg), for people to judge the methods by eye (cli/contact_sheet.h).
#include <chrono>
#include <cstdio>
#include <memory>
#include <sstream>

#include "cli/commands.h"
#include "cli/contact_sheet.h"
#include "cli/video_encoder.h"
#include "console/command_line.h"
#include "io/png_write.h"
#include "motion/frame_range.h"

namespace sweepd::cli {

namespace {

constexpr int kMostSheetRows = 32;

struct Options {
  PosingArguments posing;
  SheetOptions sheet;
  std::filesystem::path png, video;
  int frames_per_second = 30;
};

// "0,600,1200-1203" -> 0, 600, 1200, 1201, 1202, 1203; the reason when the text is not such a
// list (an empty list included).
std::string parse_frame_list(const std::string& text, std::vector<int>& frames) {
  frames.clear();
  std::istringstream items(text);
  for (std::string item; std::getline(items, item, ',');) {
    if (const std::optional<int> frame = motion::parse_frame_number(item)) {
      frames.push_back(*frame);
    } else if (const std::optional<motion::FrameRange> range = motion::parse_frame_range(item)) {
      for (int f = range->first; f <= range->last; ++f) frames.push_back(f);
    } else {
      return "expected frames N or ranges A-B separated by commas, got '" + item + "'";
    }
  }
  if (frames.empty()) return "the frame list is empty: give frames as N,N,A-B";
  return "";
}

int sheet(Options& options) {
  const auto start = std::chrono::steady_clock::now();
  SheetOptions& sheet = options.sheet;
  options.posing.frames = {*std::min_element(sheet.frames.begin(), sheet.frames.end()),
                           *std::max_element(sheet.frames.begin(), sheet.frames.end())};
  PosedModel posed(options.posing);  // refuses frames past the clip's end, naming them
  gpu::Context context;
  ContactSheet contact(posed, sheet, context);
  const int width = contact.width();
  const std::size_t columns = sheet.methods.size();
  if (!options.png.empty()) {
    const int rows = static_cast<int>(sheet.frames.size());
    const int height = rows * sheet.cell_height;
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width) * height * 4);
    for (int row = 0; row < rows; ++row) contact.render_row(row, rgba, row);
    io::write_png(options.png, width, height, rgba);
    std::printf("wrote %s (%dx%d: %d frames x %zu methods, %s)\n", options.png.string().c_str(),
                width, height, rows, columns, context.renderer().c_str());
    std::printf("worst edge stretch %%:\n%8s", "frame");
    for (const MethodChoice& m : sheet.methods) std::printf(" %14s", m.name.c_str());
    for (int row = 0; row < rows; ++row) {
      std::printf("\n%8d", sheet.frames[row]);
      for (std::size_t m = 0; m < columns; ++m)
        std::printf(" %14.1f", 100.0 * contact.worst_stretch()[row * columns + m]);
    }
    std::printf("\n");
  }
  if (!options.video.empty()) {
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width) * sheet.cell_height * 4);
    VideoEncoder video(options.video, width, sheet.cell_height, options.frames_per_second);
    for (std::size_t f = 0; f < sheet.frames.size(); ++f) {
      contact.render_row(f, rgba, 0);
      video.add_frame(rgba);
    }
    video.finish();
    std::printf("wrote %s (%dx%d, %zu frames at %d fps, %zu methods side by side)\n",
                options.video.string().c_str(), width, sheet.cell_height, sheet.frames.size(),
                options.frames_per_second, columns);
  }
  if (const std::string collision = contact.collision_summary(); !collision.empty())
    std::printf("%s\n", collision.c_str());
  std::printf("took %.1f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

}  // namespace

Command add_sheet_command(CLI::App& sweepctl) {
  CLI::App* command = sweepctl.add_subcommand(
      "sheet",
      "contact sheet: a PNG grid of renders, a row per frame, a column per method (or --video)");
  auto options = std::make_shared<Options>();
  add_model_and_clip_flags(*command, options->posing)->required();
  const CLI::Validator frame_list(
      [](std::string& text) -> std::string {
        std::vector<int> frames;
        return parse_frame_list(text, frames);
      },
      "");
  command->add_option("--frames", "clip frames, 0-based: N or A-B, comma-separated; a row each")
      ->type_name("LIST")
      ->check(frame_list)
      ->each([options](const std::string& text) { parse_frame_list(text, options->sheet.frames); })
      ->required();
  console::add_choice_list(
      *command, "--methods", methods_by_name(),
      [options](const MethodChoice& method) { options->sheet.methods.push_back(method); },
      "comma-separated methods, a column each (default: sweep,lbs,dqs)")
      ->type_name("LIST");
  CLI::Option* png =
      command->add_option("-o", options->png, "where to write the sheet")->type_name("OUT.png");
  CLI::Option* video =
      command
          ->add_option("--video", options->video,
                       "also (or instead) an .mp4 of the frames, methods side by side (ffmpeg)")
          ->type_name("OUT.mp4");
  command->add_option("--fps", options->frames_per_second, "--video's frames per second")
      ->type_name("N")
      ->check(console::whole_number(1, 240))
      ->capture_default_str();
  command
      ->add_option("--cell",
                   "a cell's width and height in pixels (default 240x320), each 64 to 2048")
      ->type_name("WxH")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            int w = 0, h = 0;
            char x = 0, extra = 0;
            if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || x != 'x' ||
                w < ContactSheet::kSmallestCell || h < ContactSheet::kSmallestCell || w > 2048 ||
                h > 2048)
              return "expected WxH with W and H from 64 to 2048, got '" + text + "'";
            return "";
          },
          ""))
      ->each([options](const std::string& text) {
        std::sscanf(text.c_str(), "%dx%d", &options->sheet.cell_width, &options->sheet.cell_height);
      });
  command->add_option("--focus", options->sheet.focus, "close-ups: the camera frames this joint")
      ->type_name("JOINT")
      ->check(CLI::IsMember(focus_names()));
  command->add_option("--heat", "colour the skin by edge stretch, blue 0 to red at --heat-scale")
      ->type_name("stretch")
      ->check(CLI::IsMember({"stretch"}))
      ->each([options](const std::string&) { options->sheet.heat = true; });
  command->add_option("--heat-scale", "the stretch shown red, in percent (default 100)")
      ->type_name("PERCENT")
      ->check(console::whole_number(1, 1000))
      ->each([options](const std::string& percent) {
        options->sheet.heat_full_scale = std::stof(percent) / 100.0f;
      });
  command
      ->add_option("--azimuth", options->sheet.azimuth_degrees,
                   "camera turned from the body's front towards its left, degrees")
      ->type_name("DEG")
      ->check(CLI::Range(-360.0f, 360.0f))
      ->capture_default_str();
  command
      ->add_option("--elevation", options->sheet.elevation_degrees,
                   "camera raised above the body's centre, degrees")
      ->type_name("DEG")
      ->check(CLI::Range(-80.0f, 80.0f))
      ->capture_default_str();
  add_collision_flag(*command, options->posing);
  command->callback([options, png, video] {
    if (png->count() == 0 && video->count() == 0)
      throw CLI::ValidationError("give -o OUT.png, --video OUT.mp4 or both");
    if (png->count() > 0 && options->sheet.frames.size() > kMostSheetRows)
      throw CLI::ValidationError("--frames: " + std::to_string(options->sheet.frames.size()) +
                                 " frames make too many sheet rows (at most " +
                                 std::to_string(kMostSheetRows) + "); give fewer, or only --video");
    if (options->sheet.methods.empty())
      for (const char* name : {"sweep", "lbs", "dqs"})
        options->sheet.methods.push_back(methods_by_name().at(name));
    options->sheet.collision = options->posing.collision;
  });
  return {command, [options] { return sheet(*options); }};
}

}  // namespace sweepd::cli
