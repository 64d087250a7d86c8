// glint — building the render scene from a validated description.
#pragma once

#include <map>
#include <utility>
#include <vector>

#include "renderer/scene.h"
#include "scenes/description.h"

namespace glint {

struct BuildTimings {
  double acceleratorSeconds = 0;  // Embree (or kd-tree) build
  double totalSeconds = 0;        // everything, including the accelerator
};

// Which render materials a build made of each description material (buildRenderScene records
// it when asked), so that refreshMaterials can replace just those.
struct MaterialUses {
  struct Made {
    uint32_t index;     // in RenderScene::materials
    bool vertexColors;  // made for meshes with vertex colours
  };
  struct Use {
    std::vector<Made> made;
    bool tangentSpace = false;  // it shades in tangent space (derivedTangents made tangents)
  };
  std::map<int, Use> ofDescription;  // description material -> what was made of it
  std::vector<int> meshMaterial;     // per geometry mesh: its description material (-1 default)
  // The textures made, by (description texture, sRGB): a remade material reads the same ones.
  std::map<std::pair<int, bool>, const Texture*> textures;
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
  // When given, filled with what was made of each description material (refreshMaterials).
  MaterialUses* materialUses = nullptr;
};
RenderScene buildRenderScene(const SceneDescription& desc, BuildTimings* timings = nullptr,
                             const BuildOptions& options = {});

// What refreshRenderScene makes again.
inline constexpr uint32_t kRefreshCamera = 1;  // the selected camera and its placement
inline constexpr uint32_t kRefreshLights = 2;  // the scene's own lights and environment

// Brings `scene`, built by buildRenderScene from an earlier version of `desc`, up to date where
// only what `what` names changed: the camera placed anew (RenderScene::setCamera), the lights
// made again (setLights); the geometry and its accelerator, the materials, textures and decoded
// images stay as they are. Returns false, having changed nothing, when the change needs a whole
// build instead: the frame's shutter is open (it decides how the geometry was built), a light
// reads a texture (which lives among the scene's textures), or the scene has no light of its
// own (the studio light is the whole build's decision). Throws SceneError as buildRenderScene.
bool refreshRenderScene(const SceneDescription& desc, uint32_t what, RenderScene* scene);

// Replaces the render materials made of description materials `changed` (`uses`, recorded by
// the build of `scene`) with ones made from `desc` (RenderScene::replaceMaterial: the emitting
// surfaces' lights are made again); the geometry and its accelerator, the textures and the
// scene's own lights stay. Returns false, having changed nothing, when the change needs a whole
// build: a material reads a texture the scene has not made (textures live among the scene's),
// turns its meshes single-
// or double-sided or refracting (the accelerator culls back faces by it), needs tangents its
// meshes were not given (or were given for it), or goes from unlit to lit or back (which
// decides the studio light). Throws SceneError as buildRenderScene.
bool refreshMaterials(const SceneDescription& desc, const std::vector<int>& changed,
                      const MaterialUses& uses, RenderScene* scene);

// The image size the description asks for: explicit width/height, else derived from the
// selected camera's aspect (640 wide by default).
void resolveImageSize(const SceneDescription& desc, const CameraDesc* camera, int* width,
                      int* height);

// The image size buildRenderScene gives `desc`, without building it (the camera named in
// desc.render.camera, else the first). Throws SceneError for an unknown camera name.
void imageSize(const SceneDescription& desc, int* width, int* height);

}  // namespace glint
