#include "deform/job/anatomical_features.h"

namespace sweepd::deform {

std::string to_string(const AnatomicalFeatures& features) {
  std::string list;
  auto add = [&](bool on, const char* name) {
    if (!on) return;
    if (!list.empty()) list += ',';
    list += name;
  };
  add(features.folding, "folding");
  add(features.protrusion, "protrusion");
  add(features.volume, "volume");
  add(features.bulge, "bulge");
  return list;
}

void FeatureApplier::select(const AnatomicalFeatures& features, Deformer& deformer) {
  if (deformer.options().preserve_volume != features.volume ||
      deformer.options().muscle_bulge != features.bulge) {
    DeformOptions options = deformer.options();
    options.preserve_volume = features.volume;
    options.muscle_bulge = features.bulge;
    deformer.set_options(std::move(options));
  }
  if (features.collision() && !collision_) collision_ = std::make_unique<CollisionFeatures>(bound_);
  if (collision_) collision_->select(features.folding, features.protrusion);
  selected_ = features;
}

FeatureReport FeatureApplier::apply(const Deformer& deformer, std::span<glm::vec3> positions,
                                    std::span<glm::vec3> normals) {
  if (!selected_.collision()) return {};
  const FeatureReport report = collision_->apply(deformer.skinning(), positions);
  if (report.folded + report.protruded == 0 || normals.empty()) return report;
  const CollisionRegions& regions = collision_->regions();
  welded_normals_.assign(positions.size(), glm::vec3(0.0f));
  const std::vector<std::uint32_t>& indices = regions.welded_indices;
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const glm::vec3& a = positions[indices[t]];
    const glm::vec3 area_normal =
        glm::cross(positions[indices[t + 1]] - a, positions[indices[t + 2]] - a);
    for (int k = 0; k < 3; ++k) welded_normals_[indices[t + k]] += area_normal;
  }
  for (std::size_t v = 0; v < normals.size(); ++v) {
    const glm::vec3& n = welded_normals_[regions.representative[v]];
    const float length = glm::length(n);
    normals[v] = length > 0.0f ? n / length : glm::vec3(0, 1, 0);
  }
  return report;
}

}  // namespace sweepd::deform
