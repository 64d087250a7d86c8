// glint — the Python module's scene: loaded once, rendered many times.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "python/rendered_image.h"
#include "renderer/integrator.h"
#include "renderer/scene.h"
#include "scenes/build.h"
#include "scenes/load.h"
#include "scenes/scene_info.h"

namespace glint::python {

class ProgressiveSession;

// A loaded scene (its files read and decoded once), its description at the scene time, and the
// render scene built from it, kept between renders: a render whose options do not change what
// the build depends on (image size, camera, accelerator, integrator, shutter, background,
// default light, variant, scene time) reuses it.
class SceneHandle {
 public:
  // SCENE (a .gltf/.glb, .ply/.obj or glint .json file) with a sidecar file (or the automatic
  // NAME.glint.json). Throws SceneError.
  SceneHandle(const std::string& path, const std::optional<std::string>& sidecar,
              std::optional<double> time);
  // JSON given as text (SceneLoader::JsonText): a glint .json scene, or the sidecar of `scene`.
  SceneHandle(const SceneLoader::JsonText& json, const std::optional<std::string>& scene,
              std::optional<double> time);

  const std::string& file() const { return file_; }  // names the scene in messages
  const SceneDescription& description() const { return desc_; }

  // What `glint info` prints of the scene at its loaded time (builds the render scene a render
  // with the scene's own settings then reuses).
  SceneInfo info();

  // Renders with `options`, a JSON object of the sidecar's render-block keys ("spp", "seed",
  // "threads", "camera", "integrator", "width", ...) and the module's own: "time" (seconds:
  // the scene evaluated then), "time_limit" (seconds), "noise_target", "crop" ([x0, y0, x1,
  // y1]) and "aovs". Errors name `caller` ("render()") and the key. `cancel` stops the render;
  // the passes done are returned. Throws SceneError (bad options), InputError or FailureError.
  std::shared_ptr<RenderedImage> render(const std::string& options,
                                        const std::atomic<bool>* cancel);
  // The same render pass by pass (ProgressiveSession::next).
  std::unique_ptr<ProgressiveSession> progressive(const std::string& options);

  // Applies `patch`, a JSON object in the sidecar's schema, to the scene as a second sidecar
  // would (a camera or material named like an existing one changes it, render keys replace the
  // scene's, lights and objects are added), for every render after it; the files are not read
  // again. Errors name "update()". Throws SceneError.
  void update(const std::string& patch);
  // Sets the intensity and/or colour of the light named `name` for the renders after it.
  // Throws SceneError (no such light, a negative or non-finite value).
  void setLight(const std::string& name, std::optional<float> intensity, std::optional<Rgb> color);

  // Render scenes built so far: a render that reuses the last one builds none.
  int builds() const { return builds_; }
  // Render scenes brought up to date without a build (refreshRenderScene: a camera or lights
  // changed; refreshMaterials: a material's parameters).
  int refreshes() const { return refreshes_; }
  // How long loading the files took, and the last build (accelerator included).
  double loadSeconds() const { return loadSeconds_; }
  const BuildTimings& lastBuild() const { return lastBuild_; }

 private:
  struct Request;
  struct Prepared;
  Request request(const std::string& options, const std::string& caller) const;
  // The render scene and integrator for a request (building the scene only when its build
  // settings changed).
  Prepared prepare(const std::string& options, const std::string& caller);
  // The render scene for `desc`: the last one when its build settings are the same.
  std::shared_ptr<const RenderScene> built(const SceneDescription& desc);

  std::mutex mutex_;  // one render or build at a time (Python threads may share a scene)
  std::string file_;
  std::unique_ptr<SceneLoader> loader_;
  SceneDescription desc_;
  std::shared_ptr<RenderScene> scene_;  // shared with progressive renders under way
  RenderSettings builtWith_;
  std::shared_ptr<TextureImages> images_;  // decoded once, for every build
  // The changes made since loading (update, setLight), applied again to the description at
  // another scene time; `version_` counts them, and a render scene built at another version
  // is built again.
  std::vector<std::function<void(SceneDescription*)>> edits_;
  int version_ = 0, builtVersion_ = 0;
  // What the edits since the last build changed (kRefreshCamera, kRefreshLights,
  // kRefreshMaterials: the description materials in changedMaterials_), or kRebuild: something
  // only a build makes.
  static constexpr uint32_t kRefreshMaterials = 1u << 30;
  static constexpr uint32_t kRebuild = 1u << 31;
  uint32_t changed_ = 0;
  std::vector<int> changedMaterials_;
  MaterialUses materialUses_;  // what the last build made of each description material
  // Brings scene_ up to date with `desc` for what changed_ names; false: it needs a build.
  bool refresh(const SceneDescription& desc);
  // What a "materials" patch changes: kRefreshMaterials for parameters of materials the scene
  // has, kRebuild for a new material or one assigned to nodes.
  uint32_t materialsChange(const nlohmann::json& materials);
  int builds_ = 0, refreshes_ = 0;
  double loadSeconds_ = 0;
  BuildTimings lastBuild_;
};

// A progressive render: the passes of a render one call at a time, each call's image a copy of
// the film after it. It keeps its render scene alive.
class ProgressiveSession {
 public:
  ProgressiveSession(std::shared_ptr<const RenderScene> scene,
                     std::unique_ptr<Integrator> integrator, const RenderSettings& settings,
                     const RenderOptions& options, const RenderBudget& budget, std::string file);
  // Renders the next pass and returns the image after it, or null when the render is over (its
  // budget met, or cancelled: the pass in flight dropped). The image's `running` says whether
  // another pass follows.
  std::shared_ptr<RenderedImage> next();
  std::atomic<bool>& cancel() { return cancel_; }

 private:
  std::atomic<bool> cancel_{false};
  std::shared_ptr<const RenderScene> scene_;
  std::unique_ptr<Integrator> integrator_;
  RenderSettings settings_;
  std::string file_, integratorName_;
  std::unique_ptr<BudgetedRender> render_;
  bool over_ = false;
};

}  // namespace glint::python
