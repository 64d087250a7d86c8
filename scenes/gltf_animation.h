// glint — glTF animations into keyframe tracks per node (scenes/animation.h's Track).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "scenes/animation.h"
#include "scenes/gltf_accessors.h"
#include "scenes/gltf_document.h"

namespace glint::gltf {

// A node's animated rest values (an empty track: not animated).
struct NodeTracks {
  Track<Vec3f> translation, scale;
  Track<Quaternion> rotation;
};

// Every channel of the file's animations, by glTF node index.
struct AnimationTracks {
  std::map<int, NodeTracks> nodes;
  std::map<int, std::vector<Track<float>>> weights;  // one track per morph target
};

// Every animation in the file plays at once, on one clock: glTF files usually hold one
// animation, and a viewer's "play all" is the only choice that needs no name. When two
// animations drive the same property, the first one wins (with a warning in `warnings`), and
// a weights channel of a node without morph targets is ignored (with a warning). Key times
// must be finite, >= 0 and strictly increasing, values finite, rotations non-zero (they are
// normalised) and scales without a zero component: SceneErrors at the sampler otherwise.
AnimationTracks readAnimations(const Document& doc, const AccessorReader& reader,
                               std::vector<std::string>* warnings);

}  // namespace glint::gltf
