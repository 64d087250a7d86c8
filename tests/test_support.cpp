// glint tests — shared helpers.
#include "test_support.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "renderer/environment_light.h"
#include "renderer/light_sampler.h"
#include "scenes/build.h"
#include "scenes/sidecar.h"

namespace glint::test {

std::string dataDir() { return GLINT_TEST_DATA; }

std::string sourceDir() { return GLINT_SOURCE_DIR; }

std::string assetsDir() {
  if (const char* env = std::getenv("GLINT_ASSETS"); env && *env) return env;
  return GLINT_DEFAULT_ASSETS;
}

std::string testOutputDir() {
  const char* root = std::getenv("GLINT_TEST_OUTPUT");
  return root && *root ? root : "test_output";
}

std::string scratchDir(const std::string& name) {
  std::filesystem::path dir = std::filesystem::path(testOutputDir()) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::vector<std::string> listFolder(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

CommandResult runGlint(const std::string& args) {
  static int counter = 0;
  std::string base = std::filesystem::temp_directory_path() /
                     ("glint_cmd_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  std::string cmd = std::string("'") + GLINT_EXECUTABLE + "' " + args + " >'" + base + ".out' 2>'" +
                    base + ".err' </dev/null";
  int status = std::system(cmd.c_str());
  CommandResult r;
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(base + ".out");
  r.err = slurp(base + ".err");
  std::filesystem::remove(base + ".out");
  std::filesystem::remove(base + ".err");
  return r;
}

int startGlint(const std::string& args, const std::string& out, const std::string& err) {
  const std::string command = std::string("exec '") + GLINT_EXECUTABLE + "' " + args;
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = err == out ? o : ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(o, 1);
    ::dup2(e, 2);
    ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return int(pid);
}

int waitGlint(int pid) {
  int status = 0;
  ::waitpid(pid_t(pid), &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1000 + WTERMSIG(status);
}

ScopedEnv::ScopedEnv(const char* name, const char* value) : name_(name) {
  if (const char* old = std::getenv(name)) old_ = old;
  if (value)
    ::setenv(name, value, 1);
  else
    ::unsetenv(name);
}

ScopedEnv::~ScopedEnv() {
  if (old_)
    ::setenv(name_.c_str(), old_->c_str(), 1);
  else
    ::unsetenv(name_.c_str());
}

void useUniformEnvironment(RenderScene* scene, Rgb L) {
  // The scene's own lights give way to the environment; emitting surfaces stay lights.
  std::vector<std::unique_ptr<Light>> lights;
  lights.push_back(std::make_unique<UniformEnvironmentLight>(L));
  scene->setLights(std::move(lights));
  scene->setLightSampler("power");
}

Rendered renderJson(const std::string& text) {
  SceneDescription d;
  d.file = "scene.json";
  applySceneJsonText(text, d.file, SceneJsonKind::Scene, &d);
  RenderScene scene = buildRenderScene(d);
  auto integrator = makeIntegrator(scene, d.render);
  Rendered r;
  r.features = scene.features();
  r.film = render(scene, *integrator, d.render, {.threads = 2}, &r.stats);
  return r;
}

std::string cornellBoxJson(int size, int spp, uint64_t seed, const std::string& integrator,
                           bool pointLight) {
  const std::string light =
      pointLight ? R"({"type": "point", "position": [0, 1.7, 0], "intensity": 3})"
                 : R"({"type": "quad", "corner": [-0.3, 1.99, -0.3], "edge_u": [0.6, 0, 0],
                      "edge_v": [0, 0, 0.6], "intensity": 10})";
  return R"({
    "render": {"width": )" +
         std::to_string(size) + R"(, "height": )" + std::to_string(size) + R"(, "spp": )" +
         std::to_string(spp) + R"(, "seed": )" + std::to_string(seed) +
         R"(, "camera": "c", "integrator": )" + integrator + R"(},
    "cameras": [{"name": "c", "position": [0, 1, 0.95], "look_at": [0, 1, -1],
                 "yfov_degrees": 70}],
    "lights": [)" +
         light + R"(],
    "materials": [{"name": "white", "type": "lambert", "diffuse": [0.7, 0.7, 0.7]},
                  {"name": "red", "type": "lambert", "diffuse": [0.7, 0.12, 0.1]},
                  {"name": "green", "type": "lambert", "diffuse": [0.12, 0.6, 0.15]}],
    "objects": [
      {"type": "quad", "corner": [-1, 0, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2], "material": "white"},
      {"type": "quad", "corner": [-1, 2, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2], "material": "white"},
      {"type": "quad", "corner": [-1, 0, -1], "edge_u": [2, 0, 0], "edge_v": [0, 2, 0], "material": "white"},
      {"type": "quad", "corner": [-1, 0, 1], "edge_u": [2, 0, 0], "edge_v": [0, 2, 0], "material": "white"},
      {"type": "quad", "corner": [-1, 0, -1], "edge_u": [0, 0, 2], "edge_v": [0, 2, 0], "material": "red"},
      {"type": "quad", "corner": [1, 0, -1], "edge_u": [0, 0, 2], "edge_v": [0, 2, 0], "material": "green"},
      {"type": "box", "min": [-0.6, 0, -0.6], "max": [-0.1, 0.9, -0.1], "material": "white"},
      {"type": "sphere", "center": [0.45, 0.35, -0.3], "radius": 0.35, "material": "white"}]})";
}

std::string litBallJson(int width, int height) {
  return R"({
  "render": {"width": )" +
         std::to_string(width) + R"(, "height": )" + std::to_string(height) +
         R"(, "camera": "c", "integrator": {"type": "path"},
             "background": [0.2, 0.3, 0.4]},
  "cameras": [{"name": "c", "position": [0, 0, 4], "look_at": [0, 0, 0], "yfov_degrees": 30}],
  "lights": [{"type": "quad", "corner": [-0.5, 2, -0.5], "edge_u": [1, 0, 0],
              "edge_v": [0, 0, 1], "intensity": 8}],
  "materials": [{"name": "clay", "type": "lambert", "diffuse": [0.7, 0.5, 0.4]}],
  "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.7, "material": "clay"}]})";
}

Film constantFilm(int w, int h, Rgb c, bool aovs) {
  Film film(w, h, aovs);
  for (size_t i = 0; i < film.color.size(); ++i) {
    film.color[i] = c;
    film.alpha[i] = 1;
  }
  return film;
}

ImageMetadata sampleMetadata() {
  ImageMetadata meta;
  meta.scene = "scenes/cornell.gltf";
  meta.spp = 64;
  meta.seed = 18446744073709551557ull;  // needs all 64 bits
  meta.renderSeconds = 12.5;
  meta.accel = "embree";
  meta.integrator = "path";
  return meta;
}

Film aovFilm() {
  Film film(4, 3, true);
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x) {
      size_t i = film.index(x, y);
      float v = float(i) / 16.0f;  // exact in half as well as float
      film.color[i] = {v, v + 0.25f, v + 0.5f};
      film.alpha[i] = 0.75f;
      film.albedo[i] = {0.125f, 0.25f, v};
      film.normal[i] = {0, -1, 0.5f};
      film.depth[i] = 1000.0f + float(i) + 0.125f;  // not representable in half
      film.variance[i] = {v * 0.5f, 0.0625f, 2.0f};
    }
  return film;
}

}  // namespace glint::test
