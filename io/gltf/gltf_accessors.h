// glTF documents as sweepd's glTF readers (io/gltf/gltf_load.h, io/gltf/gltf_clip_load.h) read them, with
// every problem a LoadError naming the file (internal to io/):
//   parse_gltf_file(file, uris, report)  the file's bytes parsed by tinygltf (.glb or .gltf,
//                   sniffed from the bytes; images not decoded; external URIs through the policy);
//                   tinygltf's warnings go to the report
//   parse_gltf_bytes(bytes, file, uris, report)  the same for bytes already in memory (a client's
//                   upload); `file` only names them in messages
//   AccessorReader  an accessor's count × components values as doubles (byteStride, sparse,
//                   normalised integers), each bound checked, against an AccessorSpec of what the
//                   caller accepts (type, component types)
//   kFloat, kFloatOrUnorm, kJointTypes, kIndexTypes   the component types each use accepts
#pragma once

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "io/files/load_error.h"
#include "io/gltf/gltf_uri_policy.h"
#include "io/load_report.h"

namespace sweepd::io::gltf {

namespace fs = std::filesystem;

// The name of a TINYGLTF_TYPE_* ("SCALAR", "VEC3", ...), for messages.
std::string type_name(int type);
// The largest value of an integer component type (1 for float).
double max_of_integer_type(int component_type);
// One component of a TINYGLTF_COMPONENT_TYPE_* at `bytes`, as a double.
double decode_component(const unsigned char* bytes, int component_type);

// What a caller accepts from one accessor.
struct AccessorSpec {
  std::string what;  // e.g. "POSITION of mesh 0 primitive 1", for messages
  int type;          // TINYGLTF_TYPE_*
  std::vector<int> component_types;
  bool normalize_integers;  // map integer components to [0, 1] / [-1, 1]
};

// Reads glTF accessors (byteStride, sparse, normalised integers) with every bound checked, and
// turns each problem into a LoadError naming the file.
class AccessorReader {
 public:
  AccessorReader(const fs::path& file, const tinygltf::Model& gltf) : file_(file), gltf_(gltf) {}

  [[noreturn]] void fail(const std::string& reason) const { throw LoadError(file_, reason); }

  const tinygltf::Accessor& accessor(int index, const std::string& what) const {
    if (index < 0 || index >= static_cast<int>(gltf_.accessors.size()))
      fail(what + ": accessor " + std::to_string(index) + " does not exist");
    return gltf_.accessors[index];
  }

  // count * components values, as doubles, in element order.
  std::vector<double> read(int index, const AccessorSpec& spec) const {
    const tinygltf::Accessor& acc = accessor(index, spec.what);
    const std::string where = spec.what + " (accessor " + std::to_string(index) + ")";
    if (acc.type != spec.type)
      fail(where + " has type " + type_name(acc.type) + ", expected " + type_name(spec.type));
    if (std::find(spec.component_types.begin(), spec.component_types.end(), acc.componentType) ==
        spec.component_types.end())
      fail(where + " has unsupported component type " + std::to_string(acc.componentType));
    const int components = tinygltf::GetNumComponentsInType(acc.type);
    const std::size_t component_size = tinygltf::GetComponentSizeInBytes(acc.componentType);
    const std::size_t element_size = components * component_size;
    // Bounds first, so that a lying count cannot make us allocate before failing.
    ElementRange range{nullptr, 0, 0};
    if (acc.bufferView >= 0)
      range = locate(acc.bufferView, acc.byteOffset, 0, element_size, acc.count, where);
    else if (acc.count > kMaxElementsWithoutData)
      fail(where + " has count " + std::to_string(acc.count) + " but no buffer view");
    std::vector<double> values(acc.count * components, 0.0);
    for (std::size_t i = 0; i < range.count; ++i)
      for (int c = 0; c < components; ++c)
        values[i * components + c] =
            decode_component(range.element(i) + c * component_size, acc.componentType);
    if (acc.sparse.isSparse) apply_sparse(acc, where, components, component_size, values);
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(values[i]))
        fail(where + " element " + std::to_string(i / components) + " is not finite (NaN or Inf)");
    if (spec.normalize_integers && acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
      const double scale = max_of_integer_type(acc.componentType);
      for (double& value : values) value = std::max(value / scale, -1.0);  // spec: max(c/m, -1)
    }
    return values;
  }

 private:
  // An accessor's elements may be all zeros with no buffer view; cap how many we accept then.
  static constexpr std::size_t kMaxElementsWithoutData = std::size_t{1} << 22;

  // `count` elements laid out `stride` bytes apart from `base`, all inside the buffer.
  struct ElementRange {
    const unsigned char* base;
    std::size_t stride;
    std::size_t count;
    const unsigned char* element(std::size_t i) const { return base + i * stride; }
  };

  // Checks that `count` elements of `element_size` bytes at `offset` fit in the view and the
  // view in its buffer; stride 0 means the view's byteStride (or tightly packed).
  ElementRange locate(int view_index, std::size_t offset, std::size_t stride,
                      std::size_t element_size, std::size_t count, const std::string& where) const {
    if (view_index < 0 || view_index >= static_cast<int>(gltf_.bufferViews.size()))
      fail(where + " refers to missing buffer view " + std::to_string(view_index));
    const tinygltf::BufferView& view = gltf_.bufferViews[view_index];
    if (view.buffer < 0 || view.buffer >= static_cast<int>(gltf_.buffers.size()))
      fail(where + ": buffer view " + std::to_string(view_index) + " refers to missing buffer " +
           std::to_string(view.buffer));
    const std::vector<unsigned char>& data = gltf_.buffers[view.buffer].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
      fail(where + ": buffer view " + std::to_string(view_index) + " runs past the end of buffer " +
           std::to_string(view.buffer) + " (" + std::to_string(data.size()) +
           " bytes; missing or truncated buffer data)");
    if (stride == 0) stride = view.byteStride != 0 ? view.byteStride : element_size;
    if (stride < element_size)
      fail(where + " has byteStride " + std::to_string(stride) + " below its element size " +
           std::to_string(element_size));
    const unsigned char* base = data.data() + view.byteOffset;
    if (count == 0) return {base, stride, 0};
    // count <= byteLength keeps the product below from overflowing (elements are >= 1 byte).
    if (count > view.byteLength || offset > view.byteLength ||
        stride * (count - 1) + element_size > view.byteLength - offset)
      fail(where + " has " + std::to_string(count) + " elements of " +
           std::to_string(element_size) + " bytes (stride " + std::to_string(stride) +
           ") that do not fit in buffer view " + std::to_string(view_index) + " of " +
           std::to_string(view.byteLength) + " bytes (out of range)");
    return {base + offset, stride, count};
  }

  void apply_sparse(const tinygltf::Accessor& acc, const std::string& where, int components,
                    std::size_t component_size, std::vector<double>& values) const {
    const auto& sparse = acc.sparse;
    const int index_type = sparse.indices.componentType;
    if (index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      fail(where + " has sparse indices of unsupported component type " +
           std::to_string(index_type));
    if (sparse.count < 0) fail(where + " has a negative sparse count");
    const std::size_t count = static_cast<std::size_t>(sparse.count);
    const std::string sparse_where = where + " sparse";
    const std::size_t index_size = tinygltf::GetComponentSizeInBytes(index_type);
    const std::size_t element_size = components * component_size;
    const ElementRange indices = locate(sparse.indices.bufferView, sparse.indices.byteOffset,
                                        index_size, index_size, count, sparse_where + " indices");
    const ElementRange replacements =
        locate(sparse.values.bufferView, sparse.values.byteOffset, element_size, element_size,
               count, sparse_where + " values");
    for (std::size_t i = 0; i < count; ++i) {
      const double target = decode_component(indices.element(i), index_type);
      if (target >= static_cast<double>(acc.count))
        fail(sparse_where + " index " + std::to_string(i) + " is out of range");
      const std::size_t element = static_cast<std::size_t>(target);
      for (int c = 0; c < components; ++c)
        values[element * components + c] =
            decode_component(replacements.element(i) + c * component_size, acc.componentType);
    }
  }

  const fs::path& file_;
  const tinygltf::Model& gltf_;
};

inline const std::vector<int> kFloat = {TINYGLTF_COMPONENT_TYPE_FLOAT};
inline const std::vector<int> kFloatOrUnorm = {TINYGLTF_COMPONENT_TYPE_FLOAT,
                                               TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                               TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
inline const std::vector<int> kJointTypes = {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                             TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
inline const std::vector<int> kIndexTypes = {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                             TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                             TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT};

tinygltf::Model parse_gltf_file(const fs::path& file, const GltfUriPolicy& uris,
                                LoadReport* report);
tinygltf::Model parse_gltf_bytes(std::span<const unsigned char> bytes, const fs::path& file,
                                 const GltfUriPolicy& uris, LoadReport* report);

}  // namespace sweepd::io::gltf
