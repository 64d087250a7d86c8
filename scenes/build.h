// glint — building the render scene from a validated description.
#pragma once

#include "renderer/scene.h"
#include "scenes/description.h"

namespace glint {

struct BuildTimings {
  double acceleratorSeconds = 0;  // Embree (or kd-tree) build
  double totalSeconds = 0;        // everything, including the accelerator
};

// Resolves the image size and camera, bakes single placements into world space (meshes placed
// several times stay instanced), creates materials, textures and lights (the studio environment
// when the scene brings no light, a camera framing the bounds over the whole animation when it
// has no camera), computes SceneFeatures
// and builds the accelerator named in desc.render.accel. glTF images are decoded in parallel
// with the rest of the build. Throws SceneError for problems only visible now (unknown camera
// name, inconsistent sizes, image data that does not decode).
// decodeImages false leaves image textures' pixels undecoded (`glint info`, which reads no
// texel): a lookup would still decode them, on first use.
struct BuildOptions {
  bool decodeImages = true;
  // An earlier frame's images (RenderScene::images) of the same loaded files: images found
  // there (the same encoded bytes, the same file) are used as they are, decoded already, and
  // new ones are added to the set. A sequence passes each frame's set on to the next.
  std::shared_ptr<TextureImages> images;
};
RenderScene buildRenderScene(const SceneDescription& desc, BuildTimings* timings = nullptr,
                             const BuildOptions& options = {});

// The image size the description asks for: explicit width/height, else derived from the
// selected camera's aspect (640 wide by default).
void resolveImageSize(const SceneDescription& desc, const CameraDesc* camera, int* width,
                      int* height);

// The image size buildRenderScene gives `desc`, without building it (the camera named in
// desc.render.camera, else the first). Throws SceneError for an unknown camera name.
void imageSize(const SceneDescription& desc, int* width, int* height);

}  // namespace glint
