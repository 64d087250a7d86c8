// glint — emitting surfaces as lights: one area light per instance whose material emits.
#pragma once

#include "renderer/scene.h"
#include "scenes/description.h"

namespace glint {

// Adds one area light per emitting instance of scene->geometry (materials already built) and
// fills scene->instanceLight. Triangle meshes become TriangleMeshLights; analytic quads, disks
// and spheres (under a similarity transform) the matching area light, placed by the instance
// transform at the middle of the shutter. Other analytic shapes (box, cylinder, cone, plane,
// CSG trees, non-uniformly scaled spheres) still emit when a ray hits them but cannot be
// sampled, so they are not lights. Returns true when any surface emits (lights or not).
bool addEmissiveSurfaceLights(RenderScene* scene);

// The light of a sidecar quad, disk, sphere or projective light placed by `worldFromLight`;
// `slide` is the projective light's texture (or null).
std::unique_ptr<Light> makeSidecarLight(const LightDesc& l, const Transform& worldFromLight,
                                        const Texture* slide);

// The environment light: uniform for a colour, importance-sampled for an image (read here;
// a file that cannot be read is a SceneError at /environment/image).
std::unique_ptr<Light> makeEnvironmentLight(const EnvironmentDesc& env);

}  // namespace glint
