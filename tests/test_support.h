// glint tests — shared helpers: data paths, the shared asset folder, running the CLI,
// rendering a scene given as JSON text.
#pragma once

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "geometry/shape.h"
#include "image/output.h"
#include "renderer/render.h"

namespace glint::test {

// A render of a glint JSON scene: the film, its statistics and the scene's features.
struct Rendered {
  Film film;
  RenderStats stats;
  SceneFeatures features;
};
// Loads `text` as a glint .json scene (file name "scene.json"), builds it and renders it with
// its own integrator on two threads.
Rendered renderJson(const std::string& text);

// Replaces a built scene's lights (the studio a scene without lights gets) by a uniform
// environment of radiance `L`, as the sidecar's environment block would: it lights the
// scene, casts shadows and replaces the default light.
void useUniformEnvironment(RenderScene* scene, Rgb L);

// A glint JSON scene (tests/reference_images/scenes/cornell_path.json in code): a closed box
// [-1, 1] x [0, 2] x [-1, 1] of Lambert walls (red left, green right, white elsewhere) holding a
// white block and a white ball, lit by a quad light under the ceiling (or a point light), seen
// from just inside the front wall, at `size`² pixels. `integrator` is the render block's
// integrator object (JSON text).
std::string cornellBoxJson(int size, int spp, uint64_t seed, const std::string& integrator,
                           bool pointLight = false);

// A glint JSON scene: a Lambert ball under a quad light, path-traced, in front of a constant
// background (the background's samples all agree, the ball's do not), width x height pixels.
std::string litBallJson(int width, int height);

// Folder of the project's own test data (tests/data).
std::string dataDir();
// The checkout's root folder (scenes/, tests/reference_images/, ...).
std::string sourceDir();
// The shared asset folder: $GLINT_ASSETS, else the CMake setting (../shared/assets).
std::string assetsDir();
// Where tests write: $GLINT_TEST_OUTPUT (under the build tree), else ./test_output.
std::string testOutputDir();
// A fresh, empty scratch folder for one test (in testOutputDir()), named after it.
std::string scratchDir(const std::string& name);

struct CommandResult {
  int exitCode = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};
// Runs the glint executable with `args` (already shell-quoted where needed).
CommandResult runGlint(const std::string& args);
// Starts glint with `args` in the background, its stdout going to `out` and stderr to `err`
// (the same file when equal); returns its process id.
int startGlint(const std::string& args, const std::string& out, const std::string& err);
// Waits for a child process (one startGlint started): its exit code, or 1000 + the signal that
// ended it.
int waitGlint(int pid);

// The whole contents of a file ("" when it cannot be read).
std::string slurp(const std::string& path);
// The names of the entries of a folder, sorted.
std::vector<std::string> listFolder(const std::string& dir);

// Sets (or, with a null value, unsets) an environment variable for one scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value);
  ~ScopedEnv();
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  std::string name_;
  std::optional<std::string> old_;
};

// A w x h film of colour c, alpha 1 (with empty AOV channels when `aovs`).
Film constantFilm(int w, int h, Rgb c, bool aovs = false);
// A 4 x 3 film with AOVs whose every channel differs (a swapped channel cannot pass), with
// values exact in half and a depth that is not.
Film aovFilm();
// Metadata with every field set (a 64-bit seed that needs all its bits).
ImageMetadata sampleMetadata();

// The shape a scene description holds, as the type the test expects; throws (so the test
// fails, with the type it got) when it is another.
template <class T>
const T& shapeAs(const std::shared_ptr<const Shape>& shape) {
  const T* typed = dynamic_cast<const T*>(shape.get());
  if (!typed)
    throw std::runtime_error(std::string("the description holds a ") +
                             (shape ? shape->typeName() : "null shape"));
  return *typed;
}

}  // namespace glint::test
