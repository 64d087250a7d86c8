// glint — `glint preview`: a local HTTP server (cpp-httplib) showing a scene as it renders.
//
// Why cpp-httplib: a well-kept, header-only Debian package (libcpp-httplib-dev) with a thread
// pool, keep-alive and a client for the tests; the preview needs plain HTTP/1.1 on loopback,
// not Boost.Beast's asynchronous machinery or civetweb's C API and file serving. The page is
// one HTML file with plain JavaScript (apps/preview/index.html), built into the executable:
// nothing is served from disk, so no request can reach a file.
//
// The contract (paths, parameters, the state JSON, who may ask) is docs/preview.md.
#include <fmt/format.h>
#include <httplib.h>
#include <sys/random.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string_view>

#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/interrupt.h"
#include "apps/preview_page.h"  // generated from apps/preview/index.html
#include "apps/preview_session.h"
#include "image/color.h"
#include "image/output.h"
#include "image/tonemap.h"

namespace fs = std::filesystem;

namespace glint::app {

namespace {

struct PreviewArgs {
  std::string scene;
  std::optional<std::string> sidecar;
  int port = 0;
  std::string outputDir = ".";
  bool quiet = false;
  SceneOverrides overrides;
};

constexpr uint32_t kDefaultMaxSpp = 4096;

// A 400 answer: the parameter and why.
struct BadRequest : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::array<double, 3> vec3(const nlohmann::json& j, const char* key) {
  if (!j.contains(key) || !j[key].is_array() || j[key].size() != 3)
    throw BadRequest(std::string("/") + key + ": need [x, y, z]");
  std::array<double, 3> v;
  for (int i = 0; i < 3; ++i) {
    if (!j[key][size_t(i)].is_number()) throw BadRequest(std::string("/") + key + ": need numbers");
    v[size_t(i)] = j[key][size_t(i)].get<double>();
    if (!std::isfinite(v[size_t(i)])) throw BadRequest(std::string("/") + key + ": not finite");
  }
  return v;
}

CameraView parseView(const std::string& body) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(body);
  } catch (const nlohmann::json::exception& e) {
    throw BadRequest(std::string("camera: not JSON: ") + e.what());
  }
  if (!j.is_object()) throw BadRequest("camera: need an object");
  CameraView v;
  v.position = vec3(j, "position");
  v.lookAt = vec3(j, "look_at");
  if (j.contains("up")) v.up = vec3(j, "up");
  if (j.contains("yfov_degrees")) {
    if (!j["yfov_degrees"].is_number()) throw BadRequest("/yfov_degrees: need a number");
    v.yfovDegrees = j["yfov_degrees"].get<double>();
    if (!(v.yfovDegrees > 0 && v.yfovDegrees < 180))
      throw BadRequest("/yfov_degrees: must be > 0 and < 180");
  }
  const double d = std::hypot(v.lookAt[0] - v.position[0], v.lookAt[1] - v.position[1],
                              v.lookAt[2] - v.position[2]);
  if (!(d > 0)) throw BadRequest("camera: look_at must differ from position");
  return v;
}

nlohmann::json viewJson(const CameraView& v) {
  return {{"position", v.position},
          {"look_at", v.lookAt},
          {"up", v.up},
          {"yfov_degrees", v.yfovDegrees}};
}

nlohmann::json stateJson(const PreviewSnapshot& s, const ColorConfigInfo& colors) {
  nlohmann::json j;
  j["version"] = s.version;
  j["generation"] = s.generation;
  j["scene"] = s.sceneName;
  j["width"] = s.width;
  j["height"] = s.height;
  j["spp"] = s.spp;
  j["passes"] = s.passes;
  j["error"] = s.error;
  j["seconds"] = s.seconds;
  j["rendering"] = s.rendering;
  j["problem"] = s.problem ? nlohmann::json(*s.problem) : nlohmann::json(nullptr);
  j["camera"] = viewJson(s.camera);
  j["custom_camera"] = s.customCamera;
  j["bounds"] = {{"min", s.boundsMin}, {"max", s.boundsMax}};
  j["aovs"] = {"beauty", "albedo", "normal", "depth", "variance", "alpha"};
  nlohmann::json views = nlohmann::json::array();
  std::string defaultView;
  for (const DisplayViews& d : colors.displays)
    if (d.display == colors.defaultDisplay) {
      views = d.views;
      defaultView = d.defaultView;
    }
  j["views"] = views;
  j["default_view"] = defaultView;
  return j;
}

// The sidecar block for a view, as the page's "Camera JSON" shows it: ready to paste.
std::string cameraBlock(const CameraView& v) {
  const auto vec = [](const std::array<double, 3>& a) {
    return fmt::format("[{:.6g}, {:.6g}, {:.6g}]", a[0], a[1], a[2]);
  };
  return fmt::format(
      "{{\n  \"cameras\": [{{\"name\": \"preview\", \"position\": {}, \"look_at\": {}, "
      "\"up\": {},\n               \"yfov_degrees\": {:.4g}}}],\n  \"render\": {{\"camera\": "
      "\"preview\"}}\n}}\n",
      vec(v.position), vec(v.lookAt), vec(v.up), v.yfovDegrees);
}

double queryNumber(const httplib::Request& req, const char* name, double fallback, double lo,
                   double hi) {
  if (!req.has_param(name)) return fallback;
  const std::string text = req.get_param_value(name);
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(v >= lo && v <= hi))
    throw BadRequest(fmt::format("{}: need a number in [{}, {}], got '{}'", name, lo, hi, text));
  return v;
}

// Files written for one answer and read back: image/io.h writes only to files, atomically.
class ScratchFolder {
 public:
  ScratchFolder() {
    std::string pattern = (fs::temp_directory_path() / "glint-preview-XXXXXX").string();
    if (!::mkdtemp(pattern.data())) throw OutputError("cannot create a temporary folder");
    path_ = pattern;
  }
  ~ScratchFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& ext) {
    return (path_ / fmt::format("image-{}{}", counter_++, ext)).string();
  }

 private:
  fs::path path_;
  std::atomic<uint64_t> counter_{0};
};

std::string readAndRemove(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  std::error_code ec;
  fs::remove(path, ec);
  return bytes.str();
}

// The display settings a request asks for, over the scene's own.
ToneMapSettings displaySettings(const httplib::Request& req, const ToneMapSettings& scene) {
  ToneMapSettings t = scene;
  t.exposure = float(scene.exposure + queryNumber(req, "exposure", 0, -30, 30));
  if (req.has_param("tonemap")) {
    t.op = req.get_param_value("tonemap");
    if (t.op != "none" && t.op != "ward")
      throw BadRequest("tonemap: need none or ward, got '" + t.op + "'");
  }
  if (req.has_param("view")) {
    t.view = req.get_param_value("view");
    try {
      resolveDisplayView(t.display, t.view);
    } catch (const ColorError& e) {
      throw BadRequest(std::string("view: ") + e.what());
    }
  }
  return t;
}

// The PNG of one AOV of `film`. Beauty and albedo go through exposure, tone mapping (beauty)
// and the display view, as glint render's PNG output; the data AOVs are shown as values:
// normal as 0.5 + n / 2, depth over its largest value, variance as the standard error of the
// mean times 2^exposure, alpha as grey.
std::string encodePng(const Film& film, const std::string& aov, const ToneMapSettings& tonemap,
                      ScratchFolder& scratch) {
  const std::string path = scratch.file(".png");
  const size_t n = film.color.size();
  if (aov == "beauty" || aov == "albedo") {
    Film shown = film;
    if (aov == "albedo") shown.color = film.albedo;
    ToneMapSettings t = tonemap;
    if (aov == "albedo") t.op = "none", t.exposure = 0;
    LogLuminanceStats stats;
    if (t.op == "ward") stats.add(shown.color, t);
    writeDisplayImage(path, shown, t, stats.logAverage(), {});
    return readAndRemove(path);
  }
  std::vector<float> px(n * 3);
  float depthMax = 0;
  for (float d : film.depth) depthMax = std::max(depthMax, d);
  const float scale = std::exp2(tonemap.exposure);
  for (size_t i = 0; i < n; ++i) {
    Rgb v;
    if (aov == "normal") v = film.normal[i] * 0.5f + Rgb{0.5f, 0.5f, 0.5f};
    if (aov == "depth") {
      const float d = depthMax > 0 ? film.depth[i] / depthMax : 0.0f;
      v = Rgb{d, d, d};
    }
    if (aov == "variance")
      v = Rgb{std::sqrt(film.variance[i].x), std::sqrt(film.variance[i].y),
              std::sqrt(film.variance[i].z)} *
          scale;
    if (aov == "alpha") v = Rgb{film.alpha[i], film.alpha[i], film.alpha[i]};
    for (int c = 0; c < 3; ++c) px[3 * i + size_t(c)] = std::clamp(v[c], 0.0f, 1.0f);
  }
  writeRawImage(path, film.width, film.height, 3, px);
  return readAndRemove(path);
}

// ---- Who may ask: the Host, the Origin and the run's token ----
//
// Binding to 127.0.0.1 keeps other machines out, not other web pages: any page open in the
// user's browser can send requests to 127.0.0.1:PORT, and through DNS rebinding (a name of its
// own that resolves to 127.0.0.1) read the answers. So, as Jupyter's server does, a request is
// answered only when its Host names this server, when it changes nothing or comes from the
// page's own origin, and when it carries the token printed with the address.

// 256 bits from the kernel's random source (getrandom), as 64 hex digits: new each run.
std::string newToken() {
  std::array<unsigned char, 32> bytes{};
  size_t got = 0;
  while (got < bytes.size()) {
    const ssize_t n = ::getrandom(bytes.data() + got, bytes.size() - got, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0)
      throw FailureError(std::string("cannot make the preview's token: getrandom: ") +
                         std::strerror(errno));
    got += size_t(n);
  }
  std::string hex;
  for (unsigned char b : bytes) hex += fmt::format("{:02x}", b);
  return hex;
}

// Whether `given` is `secret`, in a time that does not depend on where they first differ (the
// length is no secret: every token has 64 digits).
bool sameSecret(std::string_view given, std::string_view secret) {
  if (given.size() != secret.size()) return false;
  volatile unsigned char differ = 0;  // volatile: no early exit may be compiled in
  for (size_t i = 0; i < secret.size(); ++i)
    differ = differ | static_cast<unsigned char>(given[i] ^ secret[i]);
  return differ == 0;
}

std::string lowerAscii(std::string text) {
  for (char& c : text)
    if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
  return text;
}

// The three checks, for the port the server is bound to and the run's token.
class AccessGuard {
 public:
  AccessGuard(int port, std::string token) : token_(std::move(token)), port_(std::to_string(port)) {
    for (const char* name : {"127.0.0.1", "localhost", "[::1]"}) {
      hosts_.push_back(fmt::format("{}:{}", name, port));
      origins_.push_back(fmt::format("http://{}:{}", name, port));
      // A Host without a port names port 80 (RFC 9110, 7.2; browsers leave the default port
      // out), so it is this server only when this server is on port 80.
      if (port == 80) {
        hosts_.push_back(name);
        origins_.push_back(fmt::format("http://{}", name));
      }
    }
  }
  const std::string& token() const { return token_; }

  // Why `req` is refused: a one-line answer for a 403 that never repeats the token; nullopt to
  // serve it.
  std::optional<std::string> refusal(const httplib::Request& req) const {
    // Exactly one Host, naming the loopback address and this port: a page of another name
    // that resolves to 127.0.0.1 (DNS rebinding) sends its own name.
    if (req.get_header_value_count("Host") != 1 ||
        !accepted(hosts_, lowerAscii(req.get_header_value("Host"))))
      return "refused: the Host header must name this preview (127.0.0.1:" + port_ +
             " or localhost:" + port_ + ")\n";
    // A request that changes something (the camera, a saved file) from another web page: the
    // browser says where it comes from in Origin. Without an Origin it is no browser's
    // cross-origin request; the token below still has to be right. (cpp-httplib drops a
    // header with an empty value: an empty Origin counts as none.)
    const bool changes = req.method != "GET" && req.method != "HEAD" && req.method != "OPTIONS";
    if (changes && req.has_header("Origin") &&
        (req.get_header_value_count("Origin") != 1 ||
         !accepted(origins_, lowerAscii(req.get_header_value("Origin")))))
      return "refused: another web page may not change the preview\n";
    // The token: the header X-Glint-Token (what the page sends), or the query's token (the
    // printed address, for the page itself and for tools).
    const bool inHeader = req.has_header("X-Glint-Token");
    if (!inHeader && !req.has_param("token"))
      return "refused: no token; open the address glint preview printed (it ends in "
             "?token=...)\n";
    const std::string given =
        inHeader ? req.get_header_value("X-Glint-Token") : req.get_param_value("token");
    if (!sameSecret(given, token_))
      return "refused: wrong token; open the address this glint preview printed\n";
    return std::nullopt;
  }

 private:
  static bool accepted(const std::vector<std::string>& values, const std::string& value) {
    return std::find(values.begin(), values.end(), value) != values.end();
  }

  std::string token_, port_;
  std::vector<std::string> hosts_, origins_;  // lower case
};

// ---- The command ----

ImageMetadata metadataOf(const PreviewArgs& args, const PreviewSnapshot& s) {
  ImageMetadata meta{args.scene, int(s.spp),       s.settings.seed,
                     s.seconds,  s.settings.accel, s.integrator};
  meta.time = s.settings.time;
  meta.stop = "spp";  // a pass boundary: the image glint render gives at this spp
  meta.error = s.error;
  return meta;
}

void runPreview(const PreviewArgs& args) {
  if (args.port < 0 || args.port > 65535) throw InputError("--port: must be 0 to 65535");
  PreviewOptions options;
  options.scene = args.scene;
  options.sidecar = args.sidecar;
  options.overrides = args.overrides;
  options.maxSpp = args.overrides.spp ? uint32_t(*args.overrides.spp) : kDefaultMaxSpp;
  {  // the same first check glint render makes: a missing scene is bad input, at once
    std::error_code ec;
    if (!fs::is_regular_file(args.scene, ec))
      throw InputError(args.scene + ": scene file not found");
  }
  std::error_code ec;
  fs::create_directories(args.outputDir, ec);
  if (!fs::is_directory(args.outputDir))
    throw InputError("--output-dir " + args.outputDir + ": not a folder");
  const ColorConfigInfo colors = colorConfigInfo();
  ScratchFolder scratch;

  httplib::Server server;
  // Loopback only; cpp-httplib reads bodies up to this size (a camera is a few hundred bytes).
  server.set_payload_max_length(64 * 1024);
  // Bound first: the Host and Origin checks need the port the system chose.
  const int port = args.port == 0 ? server.bind_to_any_port("127.0.0.1")
                                  : (server.bind_to_port("127.0.0.1", args.port) ? args.port : -1);
  if (port <= 0)
    throw InputError(fmt::format("--port {}: cannot listen on 127.0.0.1:{} ({})", args.port,
                                 args.port, std::strerror(errno)));
  const AccessGuard guard(port, newToken());
  // On every answer: no type sniffing of a text answer; the page's address, token included,
  // never goes out as a Referer.
  server.set_default_headers(
      {{"X-Content-Type-Options", "nosniff"}, {"Referrer-Policy", "no-referrer"}});
  PreviewSession session(options);
  const std::string stem = fs::path(args.scene).stem().string();

  // Every route is served through here: the guard first (after cpp-httplib has read the body,
  // so a refused request leaves nothing on a kept-alive connection), then the handler, its
  // BadRequest a 400. Paths with no route get 404 whoever asks: there is nothing to learn there.
  const auto serve = [&guard](auto handler) {
    return [&guard, handler](const httplib::Request& req, httplib::Response& res) {
      if (const std::optional<std::string> why = guard.refusal(req)) {
        res.status = 403;
        res.set_content(*why, "text/plain");
        return;
      }
      try {
        handler(req, res);
      } catch (const BadRequest& e) {
        res.status = 400;
        res.set_content(std::string(e.what()) + "\n", "text/plain");
      } catch (const std::exception& e) {
        res.status = 500;
        res.set_content(std::string(e.what()) + "\n", "text/plain");
      }
    };
  };

  server.Get("/", serve([](const httplib::Request&, httplib::Response& res) {
               res.set_header("Cache-Control", "no-store");
               // No other site may frame the page (and make the user drag its camera).
               res.set_header("Content-Security-Policy", "frame-ancestors 'none'");
               res.set_content(std::string(kPreviewPage, kPreviewPage_size),
                               "text/html; charset=utf-8");
             }));
  server.Get("/api/state", serve([&](const httplib::Request& req, httplib::Response& res) {
               PreviewSnapshot s;
               if (req.has_param("after")) {
                 const double after = queryNumber(req, "after", 0, 0, 1e18);
                 s = session.waitNewer(uint64_t(after), std::chrono::seconds(10));
               } else {
                 s = session.snapshot();
               }
               res.set_header("Cache-Control", "no-store");
               res.set_content(stateJson(s, colors).dump(), "application/json");
             }));
  server.Get("/api/image", serve([&](const httplib::Request& req, httplib::Response& res) {
               const std::string aov = req.has_param("aov") ? req.get_param_value("aov") : "beauty";
               if (aov != "beauty" && aov != "albedo" && aov != "normal" && aov != "depth" &&
                   aov != "variance" && aov != "alpha")
                 throw BadRequest(
                     "aov: need beauty, albedo, normal, depth, variance or alpha, "
                     "got '" +
                     aov + "'");
               const PreviewSnapshot s = session.snapshot();
               const ToneMapSettings t = displaySettings(req, s.settings.tonemap);
               if (!s.film) {
                 res.status = 503;
                 res.set_content("no pass has completed yet\n", "text/plain");
                 return;
               }
               res.set_header("Cache-Control", "no-store");
               res.set_header("X-Glint-Version", std::to_string(s.version));
               res.set_header("Access-Control-Expose-Headers", "X-Glint-Version");
               res.set_content(encodePng(*s.film, aov, t, scratch), "image/png");
             }));
  server.Post("/api/camera", serve([&](const httplib::Request& req, httplib::Response& res) {
                session.setCamera(parseView(req.body));
                res.set_content("{}", "application/json");
              }));
  server.Delete("/api/camera", serve([&](const httplib::Request&, httplib::Response& res) {
                  session.setCamera(std::nullopt);
                  res.set_content("{}", "application/json");
                }));
  server.Get("/api/camera.json", serve([&](const httplib::Request&, httplib::Response& res) {
               const std::string block = cameraBlock(session.snapshot().camera);
               std::fputs(block.c_str(), stdout);
               std::fflush(stdout);
               res.set_content(block, "application/json");
             }));
  server.Post(
      "/api/save", serve([&](const httplib::Request& req, httplib::Response& res) {
        const std::string format = req.has_param("format") ? req.get_param_value("format") : "exr";
        if (format != "exr" && format != "png")
          throw BadRequest("format: need exr or png, got '" + format + "'");
        const PreviewSnapshot s = session.snapshot();
        if (!s.film) {
          res.status = 503;
          res.set_content("no pass has completed yet\n", "text/plain");
          return;
        }
        const std::string path =
            (fs::path(args.outputDir) / (stem + "_preview." + format)).string();
        RenderSettings settings = s.settings;
        settings.tonemap = displaySettings(req, s.settings.tonemap);
        writeImage(path, *s.film, settings, metadataOf(args, s));
        if (!args.quiet) std::fprintf(stderr, "glint: saved %s (%u spp)\n", path.c_str(), s.spp);
        res.set_content(nlohmann::json{{"path", path}, {"spp", s.spp}}.dump(), "application/json");
      }));
  // Everything else: nothing on disk is served.
  server.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.body.empty())
      res.set_content(res.status == 404 ? "not found\n" : "error\n", "text/plain");
  });

  // The token is printed here and nowhere else: not in answers, errors or the messages below.
  std::printf("glint: preview at http://127.0.0.1:%d/?token=%s\n", port, guard.token().c_str());
  std::fflush(stdout);
  if (!args.quiet) std::fprintf(stderr, "glint: Ctrl-C stops the preview\n");

  // Ctrl-C: stop serving (a second one quits at once).
  InterruptGuard interrupt("glint: stopping the preview");
  std::atomic<bool> done{false};
  std::thread stopper([&] {
    while (!done && !interrupt.interrupted())
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    // The session first: it wakes the long polls, which the server waits for when it stops.
    session.stop();
    server.stop();
  });
  server.listen_after_bind();
  done = true;
  stopper.join();
  session.stop();
}

}  // namespace

void addPreviewCommand(CLI::App& app) {
  auto args = std::make_shared<PreviewArgs>();
  CLI::App* cmd = app.add_subcommand(
      "preview", "render a scene progressively and show it live in a browser (127.0.0.1 only)");
  cmd->add_option("scene", args->scene, "a .gltf/.glb, .ply/.obj or glint .json scene")->required();
  cmd->add_option("--sidecar", args->sidecar,
                  "sidecar JSON (default: NAME.glint.json beside the glTF or mesh)");
  cmd->add_option("--port", args->port, "port on 127.0.0.1 (0: any free port, printed)")
      ->capture_default_str();
  cmd->add_option("--output-dir", args->outputDir,
                  "where the page's Save writes SCENE_preview.exr/png")
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", args->quiet, "print only the address");
  args->overrides.addOptions(cmd);
  cmd->callback([args] { runPreview(*args); });
}

}  // namespace glint::app
