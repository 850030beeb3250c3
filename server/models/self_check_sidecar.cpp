#include "server/models/self_check_sidecar.h"

#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <span>
#include <string>

#include "io/files/durable_file.h"

namespace sweepd::server {
namespace {

constexpr int kSidecarVersion = 1;

nlohmann::json key_of(const io::SweepbindChecksum& binding) {
  return {{"crc32", binding.crc32}, {"payload_size", binding.payload_size}};
}

}  // namespace

void save_self_check(const std::filesystem::path& file, const SelfCheck& checked,
                     const io::SweepbindChecksum& binding) {
  nlohmann::json warnings = nlohmann::json::array();
  for (const selfcheck::RegionWarning& w : checked.warnings)
    warnings.push_back({{"region", w.region},
                        {"worse_poses", w.worse_poses},
                        {"pose_count", w.pose_count},
                        {"sweep", w.sweep},
                        {"baseline", w.baseline},
                        {"baseline_name", w.baseline_name},
                        {"pose", w.pose},
                        {"extra_flipped", w.extra_flipped},
                        {"flipped_pose", w.flipped_pose},
                        {"text", w.text}});
  const nlohmann::json sidecar = {{"version", kSidecarVersion},
                                  {"self_check_revision", selfcheck::kSelfCheckRevision},
                                  {"binding", key_of(binding)},
                                  {"poses", checked.poses},
                                  {"warnings", std::move(warnings)}};
  const std::string text = sidecar.dump(1) + "\n";
  io::write_file_durably(
      file, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

std::optional<SelfCheck> load_self_check(const std::filesystem::path& file,
                                         const io::SweepbindChecksum& binding) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  try {
    const nlohmann::json sidecar =
        nlohmann::json::parse(std::string(std::istreambuf_iterator<char>(in), {}));
    if (sidecar.at("version") != kSidecarVersion ||
        sidecar.at("self_check_revision") != selfcheck::kSelfCheckRevision ||
        sidecar.at("binding") != key_of(binding))
      return std::nullopt;
    SelfCheck checked;
    checked.poses = sidecar.at("poses").get<int>();
    for (const nlohmann::json& w : sidecar.at("warnings"))
      checked.warnings.push_back({.region = w.at("region"),
                                  .worse_poses = w.at("worse_poses"),
                                  .pose_count = w.at("pose_count"),
                                  .sweep = w.at("sweep"),
                                  .baseline = w.at("baseline"),
                                  .baseline_name = w.at("baseline_name"),
                                  .pose = w.at("pose"),
                                  .extra_flipped = w.at("extra_flipped"),
                                  .flipped_pose = w.at("flipped_pose"),
                                  .text = w.at("text")});
    return checked;
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;  // torn or not ours: check the binding again
  }
}

}  // namespace sweepd::server
