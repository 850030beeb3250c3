#include "server/models/model_lookup.h"

#include "motion/name_list.h"

namespace sweepd::server {

std::string held_models_clause(const ModelLookup& models) {
  std::vector<std::string> labels;
  for (const ModelHandle& model : models.held_models())
    labels.push_back("'" + model->name + "' (id " + std::to_string(model->id) + ")");
  if (labels.empty()) return "this server holds no model";
  return "this server holds " + motion::name_list(labels);
}

}  // namespace sweepd::server
