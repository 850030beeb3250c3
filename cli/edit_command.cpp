// sweepctl edit: stores key-ellipse edits (paper §4.2; the JSON format is in
// io/key_ellipse_edits_json.h) in a bound model's .sweepbind file, replacing the edits it had,
// so every later pose of that model applies them.
#include <cstdio>
#include <filesystem>

#include "cli/commands.h"
#include "deform/rig/rig_map.h"
#include "io/key_ellipse_edits_json.h"
#include "io/sweepbind.h"

namespace sweepd::cli {

namespace {
const char* const kUsage =
    "usage: sweepctl edit MODEL.sweepbind EDITS.json [-o OUT.sweepbind]\n"
    "  MODEL.sweepbind    a bound model (sweepctl bind)\n"
    "  EDITS.json         key-ellipse edits (format in io/key_ellipse_edits_json.h); they\n"
    "                     replace the model's edits ({\"edits\": []} removes them)\n"
    "  -o OUT.sweepbind   write there instead of over MODEL.sweepbind\n";
}  // namespace

int run_edit(const std::vector<std::string>& args) {
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  std::filesystem::path model, edits_file, out;
  std::string problem;
  for (std::size_t i = 0; i < args.size() && problem.empty(); ++i) {
    if (args[i] == "-o" && i + 1 < args.size())
      out = args[++i];
    else if (model.empty() && !args[i].starts_with("-"))
      model = args[i];
    else if (edits_file.empty() && !args[i].starts_with("-"))
      edits_file = args[i];
    else
      problem = "unexpected argument '" + args[i] + "'";
  }
  if (problem.empty() && (model.empty() || edits_file.empty()))
    problem = "need MODEL.sweepbind and EDITS.json";
  if (problem.empty() && model.extension() != ".sweepbind")
    problem = model.string() + " is not a .sweepbind file (bind it first: sweepctl bind)";
  if (!problem.empty()) {
    std::fprintf(stderr, "sweepctl edit: %s\n\n%s", problem.c_str(), kUsage);
    return 2;
  }
  if (out.empty()) out = model;
  try {
    deform::BoundModel bound = io::load_sweepbind(model);
    bound.edits = io::load_key_ellipse_edits_json(edits_file, bound);
    io::save_sweepbind(bound, out);
    std::printf("wrote %s with %zu key ellipse edit(s)\n", out.string().c_str(),
                bound.edits.edits.size());
    for (const deform::KeyEllipseEdit& e : bound.edits.edits)
      std::printf("  %s key %d, driven by %s: %zu sample(s) up to %.0f deg\n",
                  deform::to_string(bound.sweeps[e.sweep].part), e.key,
                  bound.model.skeleton.joints[e.joint].name.c_str(), e.samples.size(),
                  e.samples.back().angle_degrees);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sweepctl edit: %s\n", e.what());
    return 1;
  }
}

}  // namespace sweepd::cli
