// rest_pose: the smallest useful sweepd client, built against the installed sweepd_client
// package. Lists the server's models, loads one, poses it at rest (every joint's local
// rotation the identity) and prints what came back.
//   rest_pose HOST:PORT [MODEL]      token from $SWEEPD_TOKEN (may be empty)
// Prints one line per model ("model NAME vertices N"), then "posed NAME vertices N height H"
// (H: the posed mesh's extent along y, in metres). Exit 1 with the reason on any error.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <string>
#include <vector>

#include "client/connection.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: rest_pose HOST:PORT [MODEL]   (token from $SWEEPD_TOKEN)\n");
    return 1;
  }
  namespace protocol = sweepd::protocol;
  try {
    sweepd::client::Connection connection(argv[1]);
    const char* token = std::getenv("SWEEPD_TOKEN");
    connection.hello(token ? token : "", "rest_pose");

    auto& builder = connection.builder();
    builder.Clear();
    connection.send(protocol::finish_message(builder, protocol::CreateListModels(builder)));
    std::string first_model;
    for (const protocol::ModelSummary* model : *connection.expect<protocol::ModelList>().models()) {
      std::printf("model %s vertices %u\n", model->name()->c_str(), model->vertex_count());
      if (first_model.empty()) first_model = model->name()->str();
    }

    const protocol::ModelInfo& info = connection.load_model(argc > 2 ? argv[2] : first_model);
    const std::string name = info.name()->str();
    const std::uint32_t model_id = info.model_id();
    const std::vector<protocol::Quat> rest(info.joint_names()->size(), protocol::Quat(0, 0, 0, 1));
    builder.Clear();
    protocol::PoseFields pose;
    pose.model_id = model_id;
    pose.rotations = rest;
    connection.send(protocol::finish_message(builder, protocol::add_pose(builder, pose)));
    const protocol::PosedVertices& reply = connection.expect<protocol::PosedVertices>();
    std::vector<float> positions(3 * std::size_t{reply.vertex_count()});
    if (!protocol::copy_positions(reply, positions)) throw std::runtime_error("no positions");
    float low = std::numeric_limits<float>::max(), high = std::numeric_limits<float>::lowest();
    for (std::size_t i = 1; i < positions.size(); i += 3) {
      low = std::min(low, positions[i]);
      high = std::max(high, positions[i]);
    }
    std::printf("posed %s vertices %u height %.6f\n", name.c_str(), reply.vertex_count(),
                high - low);
    connection.close();
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "rest_pose: %s\n", error.what());
    return 1;
  }
}
