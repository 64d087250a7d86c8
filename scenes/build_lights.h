// glint — emitting surfaces as lights: one area light per instance whose material emits.
#pragma once

#include "renderer/scene.h"
#include "scenes/description.h"

namespace glint {

// Adds one area light per emitting instance of scene->geometry (materials already built) and
// fills scene->instanceLight: the instance's mesh or placed shape (at the middle of the
// shutter) with the material's emission. Shapes that cannot be sampled (planes, CSG trees)
// still emit when a ray hits them but are not lights; they are listed in
// scene->unsampledEmitters with the reason. Returns true when any surface emits.
bool addEmissiveSurfaceLights(RenderScene* scene);

// The light of a sidecar quad, disk, sphere or projective light placed by `worldFromLight`;
// `slide` is the projective light's texture (or null).
std::unique_ptr<Light> makeSidecarLight(const LightDesc& l, const Transform& worldFromLight,
                                        const Texture* slide);

// The environment light: uniform for a colour, importance-sampled for an image (read here;
// a file that cannot be read is a SceneError at /environment/image).
std::unique_ptr<Light> makeEnvironmentLight(const EnvironmentDesc& env);

}  // namespace glint
