// glint — the render and file-watching threads of `glint preview`.
#include "apps/preview_session.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "renderer/render.h"
#include "scenes/build.h"
#include "scenes/load.h"
#include "scenes/paths.h"

namespace fs = std::filesystem;

namespace glint::app {

namespace {

// What a watched file looks like now: its modification time and size, or absent.
using FileSignature = std::map<std::string, std::pair<fs::file_time_type, uintmax_t>>;

FileSignature signatureOf(const std::vector<std::string>& files) {
  FileSignature sig;
  for (const std::string& f : files) {
    std::error_code ec;
    const auto time = fs::last_write_time(f, ec);
    if (ec) {
      sig[f] = {fs::file_time_type::min(), uintmax_t(-1)};  // missing: its creation counts
      continue;
    }
    const uintmax_t size = fs::file_size(f, ec);
    sig[f] = {time, ec ? uintmax_t(-1) : size};
  }
  return sig;
}

// The files a load reads before it knows what the scene names: the scene, the sidecar given or
// the one it would find beside a glTF or mesh (which may not exist yet).
std::vector<std::string> firstFiles(const PreviewOptions& options) {
  std::vector<std::string> files{options.scene};
  if (options.sidecar) {
    files.push_back(*options.sidecar);
  } else {
    fs::path p(options.scene);
    files.push_back((p.parent_path() / (p.stem().string() + ".glint.json")).string());
  }
  return files;
}

std::array<double, 3> toArray(Vec3f v) { return {v.x, v.y, v.z}; }
Vec3f toVec(const std::array<double, 3>& a) { return {float(a[0]), float(a[1]), float(a[2])}; }

// The view a built scene's camera gives, for the page: where it is, what it looks at (the
// point along its axis nearest the bounds' centre), its up and field of view.
CameraView viewOf(const RenderScene& scene, const SceneDescription& desc) {
  CameraView view;
  const Camera& c = scene.camera();
  const Vec3f position = c.position(), forward = c.forward();
  const Bounds3f bounds = scene.geometry().bounds();
  float distance = 1;
  if (!bounds.empty()) {
    const Vec3f center = bounds.center();
    const float radius = length(bounds.upper - bounds.lower) / 2;
    distance = std::max(dot(center - position, forward), std::max(radius, 1e-3f) * 0.1f);
  }
  view.position = toArray(position);
  view.lookAt = toArray(position + forward * distance);
  view.up = toArray(c.worldFromCamera().vector({0, 1, 0}));
  view.yfovDegrees = 40;  // the framing camera's
  for (const CameraDesc& cd : desc.cameras)
    if (cd.name == scene.cameraName() && cd.type == CameraType::Perspective)
      view.yfovDegrees = double(cd.yfov) * 180.0 / kPi;
  return view;
}

// `view` as the scene's camera, at the scene's image size.
void applyView(const CameraView& view, RenderScene* scene) {
  const Vec3f eye = toVec(view.position), target = toVec(view.lookAt), up = toVec(view.up);
  const Transform worldFromCamera = Transform::lookAt(eye, target, up);
  const float yfov = float(std::clamp(view.yfovDegrees, 1.0, 170.0) * kPi / 180.0);
  scene->setCamera(Camera::perspective(worldFromCamera, yfov, scene->camera().width(),
                                       scene->camera().height(), 0.0f, kInfinity),
                   "preview");
}

}  // namespace

PreviewSession::PreviewSession(PreviewOptions options) : options_(std::move(options)) {
  snapshot_.sceneName = fs::path(options_.scene).filename().string();
  renderThread_ = std::thread([this] { renderLoop(); });
  watchThread_ = std::thread([this] { watchLoop(); });
}

PreviewSession::~PreviewSession() { stop(); }

void PreviewSession::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  cancel_ = true;
  changed_.notify_all();
  if (renderThread_.joinable()) renderThread_.join();
  if (watchThread_.joinable()) watchThread_.join();
}

PreviewSnapshot PreviewSession::snapshot() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return snapshot_;
}

PreviewSnapshot PreviewSession::waitNewer(uint64_t version,
                                          std::chrono::milliseconds timeout) const {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait_for(lock, timeout, [&] { return snapshot_.version != version || stopping_; });
  return snapshot_;
}

void PreviewSession::setCamera(std::optional<CameraView> view) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    camera_ = std::move(view);
    recamera_ = true;
  }
  cancel_ = true;
  changed_.notify_all();
}

void PreviewSession::requestRestart() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    restart_ = true;
  }
  cancel_ = true;
  changed_.notify_all();
}

void PreviewSession::publish(const std::function<void(PreviewSnapshot&)>& change) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    change(snapshot_);
    ++snapshot_.version;
  }
  changed_.notify_all();
}

void PreviewSession::watchLoop() {
  std::vector<std::string> files;
  FileSignature last;
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stopping_) {
    changed_.wait_for(lock, options_.watchInterval, [&] { return stopping_; });
    if (stopping_) break;
    // The render thread sets the files and their signature at each load.
    if (watched_ != files) {
      files = watched_;
      last = watchedSignature_;
    }
    lock.unlock();
    FileSignature now = signatureOf(files);
    lock.lock();
    if (now != last && watched_ == files) {
      last = now;
      watchedSignature_ = now;
      lock.unlock();
      requestRestart();
      lock.lock();
    }
  }
}

void PreviewSession::renderLoop() {
  // This thread's own: the scene in use and its render. A failed load keeps them.
  struct Loaded {
    SceneDescription desc;
    RenderScene scene;
    std::unique_ptr<Integrator> integrator;
    CameraView sceneView;
    Camera sceneCamera;  // the scene's own, to go back to from a page's view
    std::string sceneCameraName;
  };
  std::unique_ptr<Loaded> loaded;
  std::unique_ptr<ProgressiveRender> render;
  while (true) {
    bool reload = false, recamera = false;
    std::optional<CameraView> view;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      const auto idle = [&] {
        return !restart_ && !recamera_ && (!render || render->spp() >= options_.maxSpp);
      };
      if (!stopping_ && idle()) changed_.wait(lock, [&] { return stopping_ || !idle(); });
      if (stopping_) return;
      reload = restart_;
      recamera = recamera_;
      restart_ = recamera_ = false;
      view = camera_;
      cancel_ = false;
    }

    if (reload) {
      // Files read before the load's own list is known, with their state now: an edit during
      // the load restarts it again.
      std::vector<std::string> files = firstFiles(options_);
      FileSignature signature = signatureOf(files);
      auto fresh = std::make_unique<Loaded>();
      std::optional<std::string> problem;
      {
        NamedFileRecorder recorder;
        try {
          namingFile(options_.scene, "cannot build the scene", [&] {
            SceneLoader loader(options_.scene, options_.sidecar);
            fresh->desc = loader.at();
            options_.overrides.apply(&fresh->desc);
            fresh->desc.render.aovs = true;  // the page shows them
            fresh->scene = buildRenderScene(fresh->desc);
            fresh->integrator = makeIntegrator(fresh->scene, fresh->desc.render);
            fresh->sceneView = viewOf(fresh->scene, fresh->desc);
            fresh->sceneCamera = fresh->scene.camera();
            fresh->sceneCameraName = fresh->scene.cameraName();
          });
        } catch (const std::exception& e) {
          problem = e.what();
        }
        std::vector<std::string> named = recorder.files();
        if (!problem) {
          // Texture files a sidecar names, and the external images of the glTF files (their
          // URIs are relative to the glTF, which resolves them itself).
          for (const TextureDesc& t : fresh->desc.textures)
            if (!t.file.empty()) named.push_back(t.file);
          std::vector<fs::path> gltfFolders{fs::path(options_.scene).parent_path()};
          for (const std::string& f : recorder.files())
            if (fs::path(f).extension() == ".gltf")
              gltfFolders.push_back(fs::path(f).parent_path());
          for (const ImageDesc& image : fresh->desc.images)
            for (const fs::path& folder : gltfFolders) {
              std::error_code ec;
              const fs::path p = folder / image.name;
              if (!image.name.empty() && fs::is_regular_file(p, ec)) named.push_back(p.string());
            }
        }
        for (const std::string& f : named)
          if (std::find(files.begin(), files.end(), f) == files.end()) {
            files.push_back(f);
            signature.merge(signatureOf({f}));
          }
      }
      {
        std::lock_guard<std::mutex> lock(mutex_);
        // A failed load keeps watching what the good one named too: fixing either restarts.
        if (problem)
          for (const std::string& f : watched_)
            if (std::find(files.begin(), files.end(), f) == files.end()) {
              files.push_back(f);
              signature.merge(signatureOf({f}));
            }
        watched_ = files;
        watchedSignature_ = signature;
      }
      if (problem) {
        publish([&](PreviewSnapshot& s) {
          s.problem = problem;
          s.rendering = render && render->spp() < options_.maxSpp;
        });
        if (!render || render->spp() >= options_.maxSpp) continue;
        // Keep refining the last good scene.
        if (!loaded) continue;
      } else {
        loaded = std::move(fresh);
        recamera = true;  // a new scene: set its camera (and a new render) below
      }
    }

    if (recamera && loaded) {
      if (view) {
        applyView(*view, &loaded->scene);
      } else {
        loaded->scene.setCamera(loaded->sceneCamera, loaded->sceneCameraName);
      }
      RenderOptions options;
      options.threads = loaded->desc.render.threads;
      render = std::make_unique<ProgressiveRender>(loaded->scene, *loaded->integrator,
                                                   loaded->desc.render, options);
      const CameraView shown = view.value_or(loaded->sceneView);
      const Bounds3f bounds = loaded->scene.geometry().bounds();
      publish([&](PreviewSnapshot& s) {
        if (reload) s.problem.reset();
        ++s.generation;
        s.settings = loaded->desc.render;
        s.integrator =
            integratorName(resolveIntegrator(loaded->scene, loaded->desc.render.integrator));
        s.spp = 0, s.passes = 0, s.error = 0, s.seconds = 0;
        s.rendering = true;
        s.camera = shown;
        s.customCamera = view.has_value();
        s.width = loaded->scene.camera().width(), s.height = loaded->scene.camera().height();
        if (!bounds.empty()) {
          s.boundsMin = toArray(bounds.lower);
          s.boundsMax = toArray(bounds.upper);
        }
      });
    }
    if (!render || !loaded) continue;
    if (render->spp() >= options_.maxSpp) {
      publish([&](PreviewSnapshot& s) { s.rendering = false; });
      continue;
    }
    if (!render->renderPass(options_.maxSpp, &cancel_)) {
      render.reset();  // dropped: a restart or a new camera follows
      // Without a new render the loop would idle on the old one: make sure one is made.
      std::lock_guard<std::mutex> lock(mutex_);
      if (!restart_ && !stopping_) recamera_ = true;
      continue;
    }
    auto film = std::make_shared<const Film>(render->film());
    publish([&](PreviewSnapshot& s) {
      s.film = film;
      s.spp = render->spp();
      s.passes = render->passes();
      s.error = render->estimatedError();
      s.seconds = render->stats().renderSeconds;
      s.rendering = render->spp() < options_.maxSpp;
    });
  }
}

}  // namespace glint::app
