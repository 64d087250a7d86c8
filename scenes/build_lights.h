// glint — the lights a scene description names: sidecar lights and the environment (emitting
// surfaces are lights too, which RenderScene derives itself: renderer/surface_lights.h).
#pragma once

#include "renderer/scene.h"
#include "scenes/description.h"

namespace glint {

// The light of a sidecar quad, disk, sphere or projective light placed by `worldFromLight`;
// `slide` is the projective light's texture (or null).
std::unique_ptr<Light> makeSidecarLight(const LightDesc& l, const Transform& worldFromLight,
                                        const Texture* slide);

// The environment light: uniform for a colour, importance-sampled for an image (read here;
// a file that cannot be read is a SceneError at /environment/image).
std::unique_ptr<Light> makeEnvironmentLight(const EnvironmentDesc& env);

}  // namespace glint
