// glint — the Python module's scene (see scene_handle.h).
#include "python/scene_handle.h"

#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "image/output.h"
#include "scenes/build.h"
#include "scenes/json_reader.h"
#include "scenes/json_util.h"
#include "scenes/sidecar.h"

namespace glint::python {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Whether a render scene built with `a` serves a render with `b`: the settings buildRenderScene
// reads (scenes/build*.cpp) are the same. The rest (spp, seed, threads, adaptive sampling,
// filter, tone mapping, AOVs) only the render and the writers read.
bool sameBuild(const RenderSettings& a, const RenderSettings& b) {
  return a.width == b.width && a.height == b.height && a.camera == b.camera && a.accel == b.accel &&
         a.integrator == b.integrator && a.shutter == b.shutter && a.time == b.time &&
         a.background == b.background && a.defaultLight == b.defaultLight && a.variant == b.variant;
}

}  // namespace

struct SceneHandle::Request {
  SceneDescription desc;
  RenderBudget budget;
  std::optional<PixelWindow> crop;
};

struct SceneHandle::Prepared {
  Request request;
  std::shared_ptr<const RenderScene> scene;
  std::unique_ptr<Integrator> integrator;
  RenderOptions options;
};

SceneHandle::SceneHandle(const std::string& path, const std::optional<std::string>& sidecar,
                         std::optional<double> time)
    : file_(path) {
  const auto start = std::chrono::steady_clock::now();
  loader_ = std::make_unique<SceneLoader>(path, sidecar);
  desc_ = loader_->at(time);
  loadSeconds_ = secondsSince(start);
}

SceneHandle::SceneHandle(const SceneLoader::JsonText& json, const std::optional<std::string>& scene,
                         std::optional<double> time)
    : file_(scene ? *scene : json.file) {
  const auto start = std::chrono::steady_clock::now();
  loader_ = std::make_unique<SceneLoader>(json, scene);
  desc_ = loader_->at(time);
  loadSeconds_ = secondsSince(start);
}

void SceneHandle::update(const std::string& patch) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const std::string where = "update()";
  const nlohmann::json doc = parseSceneJson(patch, where);
  auto edit = [doc, where](SceneDescription* d) {
    SceneJsonOptions options;
    options.time = d->render.time;
    options.loadGltf = false;
    applySceneJson(doc, where, SceneJsonKind::Sidecar, d, options);
  };
  SceneDescription changed = desc_;
  edit(&changed);  // throws before anything changes
  // Cameras, lights and materials' parameters are made again in the render scene; render keys
  // decide for themselves (sameBuild); anything else (objects, media, textures) needs a build.
  uint32_t change = 0;
  for (const auto& [key, value] : doc.items()) {
    if (key == "cameras")
      change |= kRefreshCamera;
    else if (key == "lights" || key == "environment")
      change |= kRefreshLights;
    else if (key == "materials")
      change |= materialsChange(value);
    else if (key != "render")
      change |= kRebuild;
  }
  desc_ = std::move(changed);
  edits_.push_back(edit);
  ++version_;
  changed_ |= change;
}

uint32_t SceneHandle::materialsChange(const nlohmann::json& materials) {
  uint32_t change = 0;
  for (const nlohmann::json& m : materials) {  // validated by the edit: objects with a name
    const std::string name = m.at("name").get<std::string>();
    const size_t before = changedMaterials_.size();
    for (size_t i = 0; i < desc_.materials.size(); ++i)
      if (desc_.materials[i].name == name) changedMaterials_.push_back(int(i));
    // A new material, or one given to nodes, changes which mesh takes which material.
    if (changedMaterials_.size() == before || m.contains("nodes"))
      change |= kRebuild;
    else
      change |= kRefreshMaterials;
  }
  return change;
}

bool SceneHandle::refresh(const SceneDescription& desc) {
  if ((changed_ & kRefreshMaterials) &&
      !refreshMaterials(desc, changedMaterials_, materialUses_, scene_.get()))
    return false;
  changed_ &= ~kRefreshMaterials;  // done, whatever follows
  changedMaterials_.clear();
  return changed_ == 0 || refreshRenderScene(desc, changed_, scene_.get());
}

void SceneHandle::setLight(const std::string& name, std::optional<float> intensity,
                           std::optional<Rgb> color) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const std::string where = "set_light()";
  if (intensity && !(*intensity >= 0 && std::isfinite(*intensity)))
    throw SceneError({where, "/intensity"}, "must be >= 0 and finite");
  if (color && !(color->x >= 0 && color->y >= 0 && color->z >= 0 && isFinite(*color)))
    throw SceneError({where, "/color"}, "must be >= 0 and finite");
  std::vector<std::string> names;
  bool found = false;
  for (const LightDesc& l : desc_.lights) {
    names.push_back(l.name);
    found |= l.name == name;
  }
  if (!found)
    throw SceneError({where, "/name"},
                     "no light named '" + name + "'" +
                         (names.empty() ? " (the scene has no lights)"
                                        : " (lights: " + quotedNames(names) + ")"));
  auto edit = [name, intensity, color](SceneDescription* d) {
    for (LightDesc& l : d->lights) {
      if (l.name != name) continue;
      if (intensity) l.intensity = *intensity;
      if (color) l.color = *color;
    }
  };
  edit(&desc_);
  edits_.push_back(edit);
  ++version_;
  changed_ |= kRefreshLights;
}

SceneHandle::Request SceneHandle::request(const std::string& options,
                                          const std::string& caller) const {
  const nlohmann::json doc = parseSceneJson(options, caller);
  JsonReader r(doc, {caller, ""});
  Request q;
  const std::optional<double> time = r.optional<double>("time");
  if (time) {
    q.desc = loader_->at(time);
    for (const auto& edit : edits_) edit(&q.desc);
  } else {
    q.desc = desc_;
  }
  q.budget.timeLimit = r.optional<double>("time_limit", kPositive).value_or(0);
  q.budget.noiseTarget = r.optional<double>("noise_target", {.gt = 0, .lt = 1}).value_or(0);
  q.budget.sppAsked = r.has("spp");
  if (r.has("crop")) {
    const auto c = r.numbers<4>("crop", kNonNegative);
    for (double v : c)
      if (v != std::floor(v) || v > 1e9)
        throw SceneError(r.where("crop"), "expected whole pixel coordinates [x0, y0, x1, y1]");
    q.crop = PixelWindow{int(c[0]), int(c[1]), int(c[2]), int(c[3])};
  }
  if (r.has("aovs")) q.desc.render.aovs = r.get<bool>("aovs");
  readRenderBlock(r, &q.desc);
  r.finish();
  return q;
}

std::shared_ptr<const RenderScene> SceneHandle::built(const SceneDescription& desc) {
  // A camera or lights changed, and nothing else: made again in the scene, unless a
  // progressive render still holds it (then it keeps its scene, and this one is built).
  const bool edited = builtVersion_ != version_;
  if (scene_ && sameBuild(builtWith_, desc.render) && edited && !(changed_ & kRebuild)) {
    if (changed_ == 0) {  // render keys only: sameBuild has judged them
      builtVersion_ = version_;
    } else if (scene_.use_count() == 1 && refresh(desc)) {
      builtVersion_ = version_;
      changed_ = 0;
      ++refreshes_;
    }
  }
  if (!scene_ || !sameBuild(builtWith_, desc.render) || builtVersion_ != version_) {
    scene_.reset();  // its memory first, unless a progressive render holds it
    scene_ = std::make_shared<RenderScene>(buildRenderScene(
        desc, &lastBuild_, BuildOptions{.images = images_, .materialUses = &materialUses_}));
    if (scene_->images()) images_ = scene_->images();
    builtWith_ = desc.render;
    builtVersion_ = version_;
    changed_ = 0;
    changedMaterials_.clear();
    ++builds_;
  }
  return scene_;
}

SceneHandle::Prepared SceneHandle::prepare(const std::string& options, const std::string& caller) {
  Prepared p{request(options, caller)};
  const RenderSettings& settings = p.request.desc.render;
  namingFile(file_, "cannot build the scene", [&] {
    p.scene = built(p.request.desc);
    p.integrator = makeIntegrator(*p.scene, settings);
  });
  p.options.threads = settings.threads;
  p.options.crop = p.request.crop;
  return p;
}

SceneInfo SceneHandle::info() {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::shared_ptr<const RenderScene> scene;
  namingFile(file_, "cannot build the scene", [&] { scene = built(desc_); });
  return describeScene(desc_, *scene);
}

std::shared_ptr<RenderedImage> SceneHandle::render(const std::string& options,
                                                   const std::atomic<bool>* cancel) {
  const std::lock_guard<std::mutex> lock(mutex_);
  const Prepared p = prepare(options, "render()");
  const RenderSettings& settings = p.request.desc.render;
  auto image = std::make_shared<RenderedImage>();
  image->settings = settings;
  namingFile(file_, "render failed", [&] {
    const StopRule rule = stopRuleFor(settings, p.request.budget, cancel);
    image->film = std::make_shared<Film>(renderUntil(*p.scene, *p.integrator, settings, p.options,
                                                     rule, &image->stats, &image->result));
  });
  const std::string integrator = integratorName(resolveIntegrator(*p.scene, settings.integrator));
  image->meta =
      renderMetadata(file_, settings, integrator, image->result, image->stats.renderSeconds);
  return image;
}

std::unique_ptr<ProgressiveSession> SceneHandle::progressive(const std::string& options) {
  const std::lock_guard<std::mutex> lock(mutex_);
  Prepared p = prepare(options, "render_progressive()");
  if (p.request.desc.render.adaptive.subdivide > 0)
    throw InputError(
        "render_progressive(): anti-aliasing by subdivision renders in one pass; use render()");
  return std::make_unique<ProgressiveSession>(std::move(p.scene), std::move(p.integrator),
                                              p.request.desc.render, p.options, p.request.budget,
                                              file_);
}

ProgressiveSession::ProgressiveSession(std::shared_ptr<const RenderScene> scene,
                                       std::unique_ptr<Integrator> integrator,
                                       const RenderSettings& settings, const RenderOptions& options,
                                       const RenderBudget& budget, std::string file)
    : scene_(std::move(scene)),
      integrator_(std::move(integrator)),
      settings_(settings),
      file_(std::move(file)),
      integratorName_(integratorName(resolveIntegrator(*scene_, settings.integrator))) {
  // The pass schedule from 1 spp whatever the budget: a first image at once, then doublings
  // (the image at a given spp does not depend on the passes that reached it).
  StopRule rule = stopRuleFor(settings_, budget, &cancel_);
  rule.warmup = true;
  namingFile(file_, "render failed", [&] {
    render_ = std::make_unique<BudgetedRender>(*scene_, *integrator_, settings_, options, rule);
  });
}

std::shared_ptr<RenderedImage> ProgressiveSession::next() {
  if (over_) return nullptr;
  bool rendered = false;
  namingFile(file_, "render failed", [&] { rendered = render_->nextPass(); });
  if (!rendered) {
    over_ = true;
    return nullptr;
  }
  auto image = std::make_shared<RenderedImage>();
  image->settings = settings_;
  image->film = std::make_shared<Film>(render_->progressive().film());
  image->stats = render_->progressive().stats();
  // The last image says why the render ends; the others that it goes on.
  over_ = render_->stopBeforeNextPass().has_value();
  image->running = !over_;
  image->result = render_->result();
  image->meta =
      renderMetadata(file_, settings_, integratorName_, image->result, image->stats.renderSeconds);
  return image;
}

}  // namespace glint::python
