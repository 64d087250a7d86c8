// glint — what `glint preview` renders: a scene kept loaded and refined pass by pass on a
// thread of its own, restarted when its files change or the page moves the camera. The HTTP
// side (apps/preview_command.cpp) only reads snapshots and asks for restarts.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "apps/cli_common.h"
#include "renderer/film.h"
#include "renderer/settings.h"

namespace glint::app {

// A view the page asks for: a pinhole camera at `position` looking at `lookAt`.
struct CameraView {
  std::array<double, 3> position{}, lookAt{}, up{0, 1, 0};
  double yfovDegrees = 40;
};

struct PreviewOptions {
  std::string scene;
  std::optional<std::string> sidecar;
  SceneOverrides overrides;
  uint32_t maxSpp = 4096;
  std::chrono::milliseconds watchInterval{250};
};

// What the page sees at one moment. `film` is shared and never changed after publication.
struct PreviewSnapshot {
  uint64_t version = 0;              // grows with every change worth showing
  uint64_t generation = 0;           // grows with every restart
  std::string sceneName;             // file name of the scene
  std::shared_ptr<const Film> film;  // null before the first pass
  RenderSettings settings;           // of the image in `film` (tone mapping, spp cap, seed)
  std::string integrator;            // resolved name, as glint render's metadata gives it
  uint32_t spp = 0;
  int passes = 0;
  double error = 0;    // estimatedRelativeError
  double seconds = 0;  // rendering time of this generation
  bool rendering = false;
  std::optional<std::string> problem;  // the last load's error, one line
  CameraView camera;                   // the view rendered (the scene's camera when not custom)
  bool customCamera = false;
  std::array<double, 3> boundsMin{}, boundsMax{};
  int width = 0, height = 0;
};

class PreviewSession {
 public:
  explicit PreviewSession(PreviewOptions options);
  ~PreviewSession();  // stops the render and watcher threads
  PreviewSession(const PreviewSession&) = delete;
  PreviewSession& operator=(const PreviewSession&) = delete;

  PreviewSnapshot snapshot() const;
  // The snapshot once its version differs from `version`, or after `timeout`.
  PreviewSnapshot waitNewer(uint64_t version, std::chrono::milliseconds timeout) const;
  // Renders from `view` (restarting at 1 spp); nullopt: the scene's own camera again.
  void setCamera(std::optional<CameraView> view);
  // Stops both threads (also done by the destructor).
  void stop();

 private:
  void renderLoop();
  void watchLoop();
  void requestRestart();
  void publish(const std::function<void(PreviewSnapshot&)>& change);

  PreviewOptions options_;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  PreviewSnapshot snapshot_;
  std::optional<CameraView> camera_;  // under mutex_
  std::vector<std::string> watched_;  // under mutex_: files of the last load
  // under mutex_: their modification times and sizes when the load began
  std::map<std::string, std::pair<std::filesystem::file_time_type, uintmax_t>> watchedSignature_;
  bool restart_ = true;              // under mutex_: reload the files
  bool recamera_ = false;            // under mutex_: the camera changed
  bool stopping_ = false;            // under mutex_
  std::atomic<bool> cancel_{false};  // drops the pass in flight
  std::thread renderThread_, watchThread_;
};

}  // namespace glint::app
