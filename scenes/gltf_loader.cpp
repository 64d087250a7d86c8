// glint — glTF 2.0 loading: the passes from a file's bytes to the scene description.
//
// (1) The container is split (GLB chunks) and the JSON parsed once, by nlohmann, and read into
// validated structs (gltf_document.h) so that every error carries a JSON pointer. (2) The
// bytes the JSON points at are read: the BIN chunk, data URIs, files inside the scene folder
// (gltf_container.h). (3) Images, textures and materials are converted (gltf_materials.h),
// animations read into tracks (gltf_animation.h), and the node tree walked (gltf_nodes.h),
// converting each mesh's primitives on first use (gltf_meshes.h) through bounds-checked
// accessor reads (gltf_accessors.h).
#include "scenes/gltf_loader.h"

#include <algorithm>

#include "scenes/gltf_accessors.h"
#include "scenes/gltf_animation.h"
#include "scenes/gltf_container.h"
#include "scenes/gltf_document.h"
#include "scenes/gltf_materials.h"
#include "scenes/gltf_meshes.h"
#include "scenes/gltf_nodes.h"
#include "scenes/json_util.h"

namespace glint {

namespace {

void convert(const gltf::Document& doc, const gltf::Payload& payload,
             const Transform& rootTransform, SceneDescription* scene) {
  for (const std::string& w : doc.warnings) scene->warnings.push_back(w);
  for (const std::string& v : doc.variants)
    if (std::find(scene->variants.begin(), scene->variants.end(), v) == scene->variants.end())
      scene->variants.push_back(v);
  const int materialBase = int(scene->materials.size());
  gltf::convertMaterials(doc, payload, scene);
  gltf::AccessorReader reader(doc, payload);
  const gltf::AnimationTracks tracks = gltf::readAnimations(doc, reader, &scene->warnings);
  gltf::MeshConverter meshes(doc, reader, materialBase, scene);
  gltf::placeNodes(doc, reader, tracks, meshes, rootTransform, scene);
}

}  // namespace

void loadGltf(const std::string& path, SceneDescription* scene, const Transform& rootTransform) {
  // A missing file is a SceneError naming it.
  loadGltfFromMemory(readTextFile(path), path, scene, rootTransform);
}

void loadGltfFromMemory(const std::string& bytes, const std::string& path, SceneDescription* scene,
                        const Transform& rootTransform) {
  const gltf::Container file = gltf::readContainer(bytes, path);
  const gltf::Document doc = gltf::readDocument(parseJson(file.json, path), path);
  const gltf::Payload payload = gltf::readPayload(doc, file, path);

  if (scene->file.empty()) scene->file = path;
  // On error leave `scene` as it was, so a caller that recovers sees no half-loaded file.
  size_t sizes[] = {scene->images.size(), scene->textures.size(),  scene->materials.size(),
                    scene->meshes.size(), scene->instances.size(), scene->cameras.size(),
                    scene->lights.size(), scene->warnings.size(),  scene->nodes.size(),
                    scene->skins.size(),  scene->variants.size()};
  try {
    convert(doc, payload, rootTransform, scene);
  } catch (...) {
    scene->images.resize(sizes[0]);
    scene->textures.resize(sizes[1]);
    scene->materials.resize(sizes[2]);
    scene->meshes.resize(sizes[3]);
    scene->instances.resize(sizes[4]);
    scene->cameras.resize(sizes[5]);
    scene->lights.resize(sizes[6]);
    scene->warnings.resize(sizes[7]);
    scene->nodes.resize(sizes[8]);
    scene->skins.resize(sizes[9]);
    scene->variants.resize(sizes[10]);
    throw;
  }
}

}  // namespace glint
