// sweepctl positionmap: the posed model's positions (and normals) rasterised in UV space and
// written as an OpenEXR position map — what render farms ask the daemon for. With --server the
// daemon deforms and renders, and its EXR file is written as it comes.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cli/commands.h"
#include "cli/posed_model.h"
#include "cli/remote_posed_model.h"
#include "cli/subcommand.h"
#include "cli/text_format.h"
#include "gpu/egl_context.h"
#include "gpu/position_map_renderer.h"
#include "io/exr_write.h"

namespace sweepd::cli {

namespace {
const std::string kUsage =
    std::string(
        "usage: sweepctl positionmap MODEL [posing options] -o OUT.exr [--size N] [--gutter G]\n"
        "                            [--normals] [--compression zip|zips|piz|none]\n"
        "  --size N           map width and height (default 1024)\n"
        "  --gutter G         pixels of island dilation (default 0; with --server: the\n"
        "                     server's 4, the only value it renders)\n"
        "  --normals          also write N.X N.Y N.Z\n") +
    kPosingUsage;

constexpr int kServerGutter = 4;  // server/handlers/position_map_service.h

std::optional<io::ExrCompression> parse_compression(const std::string& name) {
  if (name == "zip") return io::ExrCompression::kZip;
  if (name == "zips") return io::ExrCompression::kZips;
  if (name == "piz") return io::ExrCompression::kPiz;
  if (name == "none") return io::ExrCompression::kNone;
  return std::nullopt;
}

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

int positionmap(const std::vector<std::string>& arguments, const ServerAddress* server) {
  PosingArguments posing;
  std::filesystem::path out;
  int size = 1024, gutter = server ? kServerGutter : 0;
  bool with_normals = false;
  io::ExrOptions exr;
  auto parse = [&](std::vector<std::string> args) {
    std::string problem = take_posing_arguments(args, posing);
    for (std::size_t i = 0; problem.empty() && i < args.size(); ++i) {
      const bool has_value = i + 1 < args.size();
      if (args[i] == "-o" && has_value) {
        out = args[++i];
      } else if (args[i] == "--size" && has_value) {
        if (!parse_int(args[++i], 1, 16384, size)) problem = "--size expects 1..16384";
      } else if (args[i] == "--gutter" && has_value) {
        if (!parse_int(args[++i], 0, 64, gutter)) problem = "--gutter expects 0..64";
      } else if (args[i] == "--normals") {
        with_normals = true;
      } else if (args[i] == "--compression" && has_value) {
        const auto compression = parse_compression(args[++i]);
        if (!compression)
          problem = "--compression expects zip, zips, piz or none";
        else
          exr.compression = *compression;
      } else {
        problem = "unexpected argument '" + args[i] + "'";
      }
    }
    if (problem.empty() && out.empty()) problem = "missing -o OUT.exr";
    if (problem.empty() && posing.frame_range) problem = "positionmap takes one --frame";
    if (problem.empty() && server && gutter != kServerGutter)
      problem = "--gutter: the server renders with a " + std::to_string(kServerGutter) +
                "-texel gutter only";
    return problem;
  };
  return run_subcommand("positionmap", kUsage, arguments, parse, [&] {
    if (server) {
      RemotePosedModel posed(posing, *server);
      const std::vector<std::uint8_t> file = posed.position_map(
          posing.frames.first, {size, with_normals, wire_compression(exr.compression)});
      std::ofstream stream(out, std::ios::binary);
      stream.write(reinterpret_cast<const char*>(file.data()),
                   static_cast<std::streamsize>(file.size()));
      if (!stream) throw std::runtime_error("cannot write " + out.string());
      std::printf("wrote %s (%dx%d, %s, sweepd at %s)\n", out.string().c_str(), size, size,
                  deform::to_string(posing.method), server->address.c_str());
      return 0;
    }
    PosedModel posed(posing);
    if (!posed.model().has_uvs())
      throw std::invalid_argument(posing.model.string() + " has no UVs: no position map");
    std::vector<glm::vec3> positions, normals;
    posed.deform(posing.frames.first, positions, normals);
    gpu::Context context;
    gpu::PositionMapRenderer renderer(context);
    gpu::PositionMapOptions options;
    options.width = options.height = size;
    options.gutter_pixels = gutter;
    const std::size_t texels = static_cast<std::size_t>(size) * size;
    std::vector<float> p(texels * 3), n(with_normals ? texels * 3 : 0), a(texels);
    if (!with_normals) normals.clear();
    renderer.render({posed.model().uvs, positions, normals, posed.model().indices}, options,
                    {p, n, a});
    exr.model = posed.model().name;
    exr.frame = posing.frames.first;
    exr.pose_hash = pose_hash(posed.pose(posing.frames.first));
    io::write_exr(out, {size, size, p, n, a}, exr);
    std::printf("wrote %s (%dx%d, %s, %s)\n", out.string().c_str(), size, size,
                deform::to_string(posing.method), context.renderer().c_str());
    return 0;
  });
}

}  // namespace

int run_positionmap(const std::vector<std::string>& arguments) {
  return positionmap(arguments, nullptr);
}

int run_positionmap_on_server(const std::vector<std::string>& arguments,
                              const ServerAddress& server) {
  return positionmap(arguments, &server);
}

}  // namespace sweepd::cli
