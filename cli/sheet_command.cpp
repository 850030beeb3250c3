// sweepctl sheet: a contact sheet — a PNG grid of shaded renders, one row per clip frame and one
// column per deformation method, each cell captioned with the method, the frame and the worst
// edge stretch — and with --video a side-by-side .mp4 of the methods over the frames (Debian's
// ffmpeg), for people to judge the methods by eye (gpu/sheet/contact_sheet.h). With --server the
// daemon draws the PNG (ContactSheetRequest, protocol 1.11) from the model and clip uploaded to
// it, with the same code: the same picture on the same renderer.
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <sstream>

#include "cli/commands.h"
#include "cli/local_sheet.h"
#include "cli/posed_model.h"
#include "cli/remote_posed_model.h"
#include "cli/video_encoder.h"
#include "console/command_line.h"
#include "console/frame_range.h"
#include "gpu/sheet/contact_sheet.h"
#include "io/files/write_whole_file.h"

namespace sweepd::cli {

namespace {

struct SheetCommandOptions {
  PosingArguments posing;
  sheet::SheetOptions sheet;
  std::filesystem::path png, video;
  int frames_per_second = 30;
};

// "0,600,1200-1203" -> 0, 600, 1200, 1201, 1202, 1203; the reason when the text is not such a
// list (an empty list included).
std::string parse_frame_list(const std::string& text, std::vector<int>& frames) {
  frames.clear();
  std::istringstream items(text);
  for (std::string item; std::getline(items, item, ',');) {
    if (const std::optional<int> frame = console::parse_frame_number(item)) {
      frames.push_back(*frame);
    } else if (const std::optional<console::FrameRange> range = console::parse_frame_range(item)) {
      for (int f = range->first; f <= range->last; ++f) frames.push_back(f);
    } else {
      return "expected frames N or ranges A-B separated by commas, got '" + item + "'";
    }
  }
  if (frames.empty()) return "the frame list is empty: give frames as N,N,A-B";
  return "";
}

// --video: one row of cells per frame.
void draw_video(sheet::ContactSheet& contact, const SheetCommandOptions& options) {
  const sheet::SheetOptions& grid = options.sheet;
  const int width = contact.width();
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width) * grid.cell_height * 4);
  VideoEncoder video(options.video, width, grid.cell_height, options.frames_per_second);
  for (std::size_t f = 0; f < grid.frames.size(); ++f) {
    contact.render_row(f, rgba, 0);
    video.add_frame(rgba);
  }
  video.finish();
  std::printf("wrote %s (%dx%d, %zu frames at %d fps, %zu methods side by side)\n",
              options.video.string().c_str(), width, grid.cell_height, grid.frames.size(),
              options.frames_per_second, grid.methods.size());
}

void print_picture(const SheetCommandOptions& options, const sheet::SheetPicture& picture,
                   const std::string& where) {
  const sheet::SheetOptions& grid = options.sheet;
  const std::size_t columns = grid.methods.size();
  const int rows = static_cast<int>(grid.frames.size());
  std::printf("wrote %s (%dx%d: %d frames x %zu methods, %s%s)\n", options.png.string().c_str(),
              picture.width, picture.height, rows, columns, picture.renderer.c_str(),
              where.c_str());
  std::printf("shortest and longest edge, length ratio l / l_rest:\n%8s", "frame");
  for (const deform::MethodChoice& m : grid.methods) std::printf(" %14s", m.name.c_str());
  for (int row = 0; row < rows; ++row) {
    std::printf("\n%8d", grid.frames[row]);
    for (std::size_t m = 0; m < columns; ++m) {
      const sheet::EdgeRatios& cell = picture.edge_ratios[row * columns + m];
      char range[32];
      std::snprintf(range, sizeof range, "%.2f-%.2fx", cell.shortest, cell.longest);
      std::printf(" %14s", range);
    }
  }
  std::printf("\n");
}

int run_sheet(SheetCommandOptions& options, const ServerAddress& server) {
  const auto start = std::chrono::steady_clock::now();
  const sheet::SheetOptions& grid = options.sheet;
  options.posing.frames = {*std::min_element(grid.frames.begin(), grid.frames.end()),
                           *std::max_element(grid.frames.begin(), grid.frames.end())};
  std::string collision;
  if (!server.address.empty()) {                               // -o only (the command's rules)
    RemotePosedModel remote(options.posing, server);           // uploads the model and the clip
    std::fprintf(stderr, "%s\n", remote.served_as().c_str());  // the name the server holds
    const sheet::SheetPicture picture = remote.contact_sheet(grid);
    io::write_whole_file(options.png, picture.png, "sweepctl sheet");
    print_picture(options, picture, ", sweepd at " + server.address);
    if (sheet::uses_collision(grid.methods)) collision = remote.collision_summary();
  } else {
    PosedModel posed(options.posing);  // refuses frames past the clip's end, naming them
    LocalSheet local(posed, grid);
    if (!options.png.empty()) {
      const sheet::SheetPicture picture = local.picture();
      io::write_whole_file(options.png, picture.png, "sweepctl sheet");
      print_picture(options, picture, "");
    }
    if (!options.video.empty()) draw_video(local.contact(), options);
    collision = local.collision_summary();
  }
  if (!collision.empty()) std::printf("%s\n", collision.c_str());
  std::printf("took %.1f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

}  // namespace

Command add_sheet_command(CLI::App& sweepctl, const ServerAddress& server) {
  CLI::App* command = sweepctl.add_subcommand(
      "sheet",
      "contact sheet: a PNG grid of renders, a row per frame, a column per method (or --video)");
  auto options = std::make_shared<SheetCommandOptions>();
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
  add_method_list_flag(
      *command, "--methods",
      [options](const deform::MethodChoice& method) { options->sheet.methods.push_back(method); },
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
                w < sheet::ContactSheet::kSmallestCell || h < sheet::ContactSheet::kSmallestCell ||
                w > sheet::ContactSheet::kLargestCell || h > sheet::ContactSheet::kLargestCell)
              return "expected WxH with W and H from 64 to 2048, got '" + text + "'";
            return "";
          },
          ""))
      ->each([options](const std::string& text) {
        std::sscanf(text.c_str(), "%dx%d", &options->sheet.cell_width, &options->sheet.cell_height);
      });
  command->add_option("--focus", options->sheet.focus, "close-ups: the camera frames this joint")
      ->type_name("JOINT")
      ->check(CLI::IsMember(sheet::focus_names()));
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
  command->callback([options, png, video, &server] {
    if (png->count() == 0 && video->count() == 0)
      throw CLI::ValidationError("give -o OUT.png, --video OUT.mp4 or both");
    if (!server.address.empty() && video->count() > 0)
      throw CLI::ValidationError(
          "--video is drawn here, not on a server: with --server give -o OUT.png only");
    if (png->count() > 0 && options->sheet.frames.size() > sheet::ContactSheet::kMostRows)
      throw CLI::ValidationError("--frames: " + std::to_string(options->sheet.frames.size()) +
                                 " frames make too many sheet rows (at most " +
                                 std::to_string(sheet::ContactSheet::kMostRows) +
                                 "); give fewer, or only --video");
    if (options->sheet.methods.empty())
      for (const char* name : {"sweep", "lbs", "dqs"})
        options->sheet.methods.push_back(deform::methods_by_name().at(name));
  });
  return {command, [options, &server] { return run_sheet(*options, server); }, true};
}

}  // namespace sweepd::cli
