// glint — the glTF node tree placed in the scene description: instances of meshes
// (EXT_mesh_gpu_instancing included), cameras and lights at their world placement, the nodes
// that move kept as NodeDescs with their tracks, and skins with their joints.
#pragma once

#include "scenes/description.h"
#include "scenes/gltf_accessors.h"
#include "scenes/gltf_animation.h"
#include "scenes/gltf_document.h"
#include "scenes/gltf_meshes.h"

namespace glint::gltf {

// Walks the default scene (or scene 0, or every root node when there is no scene) under
// `rootTransform`, appending to `scene` one InstanceDesc per (node, primitive, GPU instance),
// the cameras and KHR_lights_punctual lights, and the SkinDescs skinned instances use. Nodes
// whose world transform can change (animated, below an animated node, or an ancestor of one)
// become NodeDescs (under one holding `rootTransform` when that is not the identity); what
// hangs below them gets their transformNode, and its static transform holds the placement at
// time 0. Meshes are converted by `meshes` on first use.
void placeNodes(const Document& doc, const AccessorReader& reader, const AnimationTracks& tracks,
                MeshConverter& meshes, const Transform& rootTransform, SceneDescription* scene);

}  // namespace glint::gltf
