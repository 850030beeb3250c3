#include "io/assimp/assimp_convert.h"

#include <assimp/scene.h>

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <stdexcept>
#include <string>
#include <string_view>

namespace sweepd::io {

namespace {

// glTF extras become nested metadata, on which assimp 5.2.5's exporter asserts.
void strip_metadata(aiNode* node) {
  delete node->mMetaData;
  node->mMetaData = nullptr;
  for (unsigned c = 0; c < node->mNumChildren; ++c) strip_metadata(node->mChildren[c]);
}

}  // namespace

std::vector<std::uint8_t> convert_with_assimp(const std::filesystem::path& gltf,
                                              AssimpExport target,
                                              const std::function<void(aiScene&)>& edit) {
  Assimp::Importer importer;
  const aiScene* read = importer.ReadFile(gltf.string(), 0);
  if (!read) throw std::runtime_error(gltf.string() + ": " + importer.GetErrorString());
  aiScene& scene = *const_cast<aiScene*>(read);  // the importer's own copy, edited in place
  strip_metadata(scene.mRootNode);
  delete scene.mMetaData;
  scene.mMetaData = nullptr;
  if (edit) edit(scene);
  Assimp::Exporter exporter;
  const aiExportDataBlob* blob =
      exporter.ExportToBlob(&scene, target == AssimpExport::kCollada ? "collada" : "fbxa");
  if (!blob) throw std::runtime_error(gltf.string() + ": " + exporter.GetErrorString());
  const auto* data = static_cast<const char*>(blob->data);
  std::string text(data, data + blob->size);
  if (target == AssimpExport::kFbxMetres) {
    const std::string_view declared = "P: \"UnitScaleFactor\", \"double\", \"Number\", \"\", 1\n";
    const std::size_t at = text.find(declared);
    if (at == std::string::npos)
      throw std::runtime_error("assimp's FBX exporter no longer writes UnitScaleFactor 1");
    text.replace(at, declared.size(),
                 "P: \"UnitScaleFactor\", \"double\", \"Number\", \"\", 100\n");
  }
  return {text.begin(), text.end()};
}

}  // namespace sweepd::io
