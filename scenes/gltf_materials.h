// glint — glTF images, textures and materials (the core metallic-roughness model and every
// ratified KHR_materials_* extension) into the scene description.
#pragma once

#include "scenes/description.h"
#include "scenes/gltf_container.h"
#include "scenes/gltf_document.h"

namespace glint::gltf {

// Appends `doc`'s images (encoded, from `payload`; their headers read, the pixels decoded only
// when a render scene is built), textures and materials to `scene`. Texture and image indices
// are offset by what `scene` already held; a material's index in the file becomes
// `scene->materials.size()` before the call plus that index. An image too large for glint or
// that OpenImageIO cannot read is a SceneError at its pointer.
void convertMaterials(const Document& doc, const Payload& payload, SceneDescription* scene);

}  // namespace glint::gltf
