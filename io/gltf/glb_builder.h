// GlbBuilder: the one binary buffer of a .glb that io::save_gltf writes, and the buffer views and
// accessors that point into it (internal to io/).
//   add_accessor(elements, component_type, type, target)  appends the elements' bytes as a new
//     4-byte aligned buffer view (target 0: none, e.g. animation keys and inverse bind matrices)
//     with one accessor of elements.size() elements; returns the accessor's index
#pragma once

#include <tiny_gltf.h>

#include <vector>

namespace sweepd::io {

class GlbBuilder {
 public:
  explicit GlbBuilder(tinygltf::Model& gltf) : gltf_(gltf) { gltf_.buffers.resize(1); }

  template <typename T>
  int add_accessor(const std::vector<T>& elements, int component_type, int type, int target) {
    std::vector<unsigned char>& data = gltf_.buffers[0].data;
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = elements.size() * sizeof(T);
    view.target = target;
    const auto* bytes = reinterpret_cast<const unsigned char*>(elements.data());
    data.insert(data.end(), bytes, bytes + view.byteLength);
    data.resize((data.size() + 3) / 4 * 4, 0);  // every view starts 4-byte aligned
    gltf_.bufferViews.push_back(view);
    tinygltf::Accessor accessor;
    accessor.bufferView = static_cast<int>(gltf_.bufferViews.size()) - 1;
    accessor.componentType = component_type;
    accessor.type = type;
    accessor.count = elements.size();
    gltf_.accessors.push_back(accessor);
    return static_cast<int>(gltf_.accessors.size()) - 1;
  }

 private:
  tinygltf::Model& gltf_;
};

}  // namespace sweepd::io
