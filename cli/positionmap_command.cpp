// sweepctl positionmap: the posed model's positions (and normals) rasterised in UV space and
// written as an OpenEXR position map — what render farms ask the daemon for. With --server the
// daemon deforms and renders, and its EXR file is written as it comes.
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>

#include "cli/commands.h"
#include "cli/posed_model.h"
#include "cli/remote_posed_model.h"
#include "console/command_line.h"
#include "deform/model/pose_hash.h"
#include "gpu/egl_context.h"
#include "gpu/position_map_renderer.h"
#include "io/exr/exr_write.h"
#include "io/files/write_whole_file.h"

namespace sweepd::cli {

namespace {
constexpr int kServerGutter = 4;  // server/services/position_map_service.h

protocol::ExrCompression wire_compression(io::ExrCompression compression) {
  switch (compression) {
    case io::ExrCompression::kZips:
      return protocol::ExrCompression::Zips;
    case io::ExrCompression::kPiz:
      return protocol::ExrCompression::Piz;
    case io::ExrCompression::kNone:
      return protocol::ExrCompression::Uncompressed;
    default:
      return protocol::ExrCompression::Zip;
  }
}

struct PositionmapCommandOptions {
  PosingArguments posing;
  std::filesystem::path out;
  int size = 1024, gutter = 0;  // with --server: kServerGutter
  bool normals = false, half_normals = false;
  io::ExrCompression compression = io::ExrCompression::kZip;
};

int positionmap(const PositionmapCommandOptions& options, const ServerAddress& server) {
  const PosingArguments& posing = options.posing;
  const std::filesystem::path& out = options.out;
  const int size = options.size;
  if (!server.address.empty()) {
    RemotePosedModel posed(posing, server);
    std::fprintf(stderr, "%s\n", posed.served_as().c_str());  // the name the server holds
    const std::vector<std::uint8_t> file = posed.position_map(
        posing.frames.first,
        {size, options.normals, wire_compression(options.compression), options.half_normals});
    io::write_whole_file(out, file, "sweepctl positionmap");
    std::printf("wrote %s (%dx%d, %s, sweepd at %s)\n", out.string().c_str(), size, size,
                deform::to_string(posing.method), server.address.c_str());
    return 0;
  }
  PosedModel posed(posing);
  if (!posed.model().has_uvs())
    throw std::invalid_argument(posing.model.string() + " has no UVs: no position map");
  std::vector<glm::vec3> positions, normals;
  posed.deform(posing.frames.first, positions, normals);
  gpu::Context context;
  gpu::PositionMapRenderer renderer(context);
  gpu::PositionMapOptions map;
  map.width = map.height = size;
  map.gutter_pixels = options.gutter;
  const std::size_t texels = static_cast<std::size_t>(size) * size;
  std::vector<float> p(texels * 3), n(options.normals ? texels * 3 : 0), a(texels);
  if (!options.normals) normals.clear();
  renderer.render({posed.model().uvs, positions, normals, posed.model().indices}, map, {p, n, a});
  io::ExrOptions exr;
  exr.compression = options.compression;
  exr.half_normals = options.half_normals;
  exr.model = posed.model().name;
  exr.frame = posing.frames.first;
  exr.pose_hash = deform::pose_hash(posed.pose(posing.frames.first));
  io::write_exr(out, {size, size, p, n, a}, exr);
  std::printf("wrote %s (%dx%d, %s, %s)\n", out.string().c_str(), size, size,
              deform::to_string(posing.method), context.renderer().c_str());
  return 0;
}

}  // namespace

Command add_positionmap_command(CLI::App& sweepctl, const ServerAddress& server) {
  CLI::App* command =
      sweepctl.add_subcommand("positionmap", "posed positions in UV space as an OpenEXR map");
  command->footer(
      "With --server the daemon deforms and renders (its 4-texel gutter), and its EXR file is\n"
      "written as it comes: MODEL is then a local .glb/.gltf/.fbx/.dae (uploaded) or a model\n"
      "name on the server.");
  auto options = std::make_shared<PositionmapCommandOptions>();
  add_posing_flags(*command, options->posing, ClipFrames::kOne);
  add_method_flags(*command, options->posing);
  command->add_option("-o", options->out, "the map to write")->type_name("OUT.exr")->required();
  command->add_option("--size", options->size, "map width and height")
      ->type_name("N")
      ->check(console::whole_number(1, 16384))
      ->capture_default_str();
  CLI::Option* gutter =
      command
          ->add_option("--gutter", options->gutter,
                       "pixels of island dilation (with --server: the server's 4, the only "
                       "value it renders)")
          ->type_name("G")
          ->check(console::whole_number(0, 64))
          ->capture_default_str();
  command->add_flag("--normals", options->normals, "also write N.X N.Y N.Z");
  command->add_flag("--half-normals", options->half_normals,
                    "the normals as float16 (half the bytes; implies --normals)");
  console::add_choice(
      *command, "--compression", options->compression,
      std::map<std::string, io::ExrCompression>{{"zip", io::ExrCompression::kZip},
                                                {"zips", io::ExrCompression::kZips},
                                                {"piz", io::ExrCompression::kPiz},
                                                {"none", io::ExrCompression::kNone}},
      "zip (default), zips, piz or none");
  command->callback([options, gutter, &server] {
    check_method_flags(options->posing, !server.address.empty());
    options->normals = options->normals || options->half_normals;
    if (server.address.empty()) return;
    if (gutter->count() > 0 && options->gutter != kServerGutter)
      throw CLI::ValidationError(
          "--gutter",
          "the server renders with a " + std::to_string(kServerGutter) + "-texel gutter only");
    options->gutter = kServerGutter;
  });
  return {command, [options, &server] { return positionmap(*options, server); }, true};
}

}  // namespace sweepd::cli
