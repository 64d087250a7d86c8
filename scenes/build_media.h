// glint — building the media of a scene (internal to scenes/: build.cpp calls it).
#pragma once

#include "renderer/scene.h"
#include "scenes/description.h"

namespace glint {

// Builds scene->media from desc.media; leaves scene->media null when there are none, so
// media-free scenes take the media-free paths (detectFeatures sets Feature::Volumes). Call
// once the geometry, camera and lights are built: a medium filling the whole scene fills the
// box around them (bounded geometry, camera position, finite lights), enlarged by 1% of its
// diagonal, so escaping rays cross a finite amount of it.
void addMedia(const SceneDescription& desc, SceneParts* scene);

}  // namespace glint
