// sweepctl join-cache A.pc2 B.pc2 ... -o ALL.pc2: point caches of consecutive frame ranges (the
// shards `render_frames --format pc2|mdd --shard I/N` writes) joined into one
// (io/point_cache/point_cache_join.h checks one point count and contiguous frames).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "cli/commands.h"
#include "io/point_cache/point_cache_join.h"

namespace sweepd::cli {

namespace {

struct JoinCacheOptions {
  std::vector<std::filesystem::path> inputs;
  std::filesystem::path out;
};

int join_cache(const JoinCacheOptions& options) {
  const io::JoinedPointCache joined = io::join_point_caches(options.inputs, options.out);
  const io::PointCacheHeader& h = joined.header;
  if (h.format == io::PointCacheFormat::kPc2)
    std::printf("wrote %s: %d caches joined, frames %g-%g of %d vertices (PC2)\n",
                options.out.string().c_str(), joined.inputs, h.start_frame,
                h.start_frame + (h.frame_count - 1) * h.sampling, h.point_count);
  else
    std::printf("wrote %s: %d caches joined, %d frames (%.6g-%.6g s) of %d vertices (MDD)\n",
                options.out.string().c_str(), joined.inputs, h.frame_count, h.times.front(),
                h.times.back(), h.point_count);
  return 0;
}

}  // namespace

Command add_join_cache_command(CLI::App& sweepctl) {
  CLI::App* command = sweepctl.add_subcommand(
      "join-cache", "join point caches of consecutive frame ranges into one");
  command->footer(
      "The caches (PC2 or MDD, all of -o's format) may come in any order: they are joined in\n"
      "the order of their frames. One point count, and no gap or overlap between them, or an\n"
      "error names the two files and their frames. The frames' bytes are copied as they are.");
  auto options = std::make_shared<JoinCacheOptions>();
  command->add_option("CACHES", options->inputs, "the caches to join")
      ->type_name("CACHE...")
      ->required();
  command->add_option("-o", options->out, "the joined cache, FILE.pc2 or FILE.mdd")
      ->type_name("OUT")
      ->required();
  return {command, [options] { return join_cache(*options); }};
}

}  // namespace sweepd::cli
