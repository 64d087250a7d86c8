// Tests for `glint preview`'s HTTP side (docs/preview.md), with a plain client (cpp-httplib's):
// the state and image answers, restarts on edits and camera changes, a bad edit's message, the
// saved EXR against glint render, bad requests, no file served from disk, concurrent clients,
// a client that goes away, and a socket bound to loopback only. The page itself is tested in
// Chromium (tests/browser).
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <thread>

#include "test_support.h"

namespace fs = std::filesystem;

namespace glint {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

// A running `glint preview` on a small Cornell box, stopped with Ctrl-C at the end.
class Preview {
 public:
  Preview(const std::string& dir, const std::string& extra = "") : dir_(dir) {
    scene_ = dir + "/box.json";
    std::ofstream(scene_) << test::cornellBoxJson(24, 4, 5, R"({"type": "path"})");
    pid_ = test::startGlint("preview " + scene_ + " --port 0 --output-dir " + dir + "/saved " +
                                extra,
                            dir + "/out.log", dir + "/err.log");
    // The first line on stdout is the address.
    const std::regex address(R"(glint: preview at http://127\.0\.0\.1:(\d+)/)");
    for (int i = 0; i < 200 && port_ == 0; ++i) {
      std::smatch m;
      const std::string out = test::slurp(dir + "/out.log");
      if (std::regex_search(out, m, address)) port_ = std::stoi(m[1]);
      else std::this_thread::sleep_for(50ms);
    }
  }
  ~Preview() {
    if (pid_ > 0) stop();  // never kill(-1): that signals every process we may
  }
  int port() const { return port_; }
  int stop() {  // Ctrl-C: its exit code
    if (pid_ <= 0) return -1;
    ::kill(pid_t(pid_), SIGINT);
    const int code = test::waitGlint(pid_);
    pid_ = -1;
    return code;
  }
  const std::string& scene() const { return scene_; }
  httplib::Client client() const {
    httplib::Client c("127.0.0.1", port_);
    c.set_read_timeout(20, 0);
    return c;
  }
  json state(const std::string& query = "") const {
    auto r = client().Get("/api/state" + query);
    if (!r || r->status != 200) return json();
    return json::parse(r->body);
  }
  // Waits for the first load's render to finish at `spp`. (Before the first load the state
  // says rendering: false too, at generation 0: waiting on that alone races the load.)
  json waitFinished(int spp) const {
    return waitFor([spp](const json& s) {
      return s["generation"].get<int>() >= 1 && s["spp"] == spp && s["rendering"] == false;
    });
  }
  // Polls the state until `done` holds (or 30 s pass); returns the last state.
  template <class F>
  json waitFor(F done) const {
    json s;
    for (int i = 0; i < 600; ++i) {
      s = state();
      if (!s.is_null() && done(s)) return s;
      std::this_thread::sleep_for(50ms);
    }
    return s;
  }

 private:
  std::string dir_, scene_;
  int pid_ = -1;
  int port_ = 0;
};

// Replaces `path` whole (a temporary file renamed over it, as many editors save), so the
// watcher never sees it half written.
void saveAs(const std::string& path, const std::string& text) {
  std::ofstream(path + ".tmp") << text;
  fs::rename(path + ".tmp", path);
}

bool isPng(const std::string& body) { return body.rfind("\x89PNG\r\n\x1a\n", 0) == 0; }

TEST(PreviewServer, RefinesPassByPassAndServesTheImage) {
  const std::string dir = test::scratchDir("PreviewServer.Refines");
  Preview p(dir, "--spp 32");
  ASSERT_GT(p.port(), 0) << test::slurp(dir + "/err.log");
  json s = p.waitFor([](const json& s) { return s["spp"] == 32 && s["rendering"] == false; });
  EXPECT_EQ(s["spp"], 32);
  EXPECT_EQ(s["passes"], 6);  // 1 2 4 8 16 32
  EXPECT_EQ(s["width"], 24);
  EXPECT_EQ(s["scene"], "box.json");
  EXPECT_TRUE(s["problem"].is_null());
  EXPECT_GT(s["error"].get<double>(), 0);
  EXPECT_FALSE(s["custom_camera"].get<bool>());
  EXPECT_NEAR(s["camera"]["position"][2].get<double>(), 0.95, 1e-6);  // the scene's camera

  auto page = p.client().Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->body.find("<html"), std::string::npos);
  for (const char* aov : {"beauty", "albedo", "normal", "depth", "variance", "alpha"}) {
    auto img = p.client().Get(std::string("/api/image?aov=") + aov + "&exposure=1&tonemap=ward");
    ASSERT_TRUE(img) << aov;
    EXPECT_EQ(img->status, 200) << aov;
    EXPECT_TRUE(isPng(img->body)) << aov;
    EXPECT_EQ(img->get_header_value("X-Glint-Version"), std::to_string(s["version"].get<int>()));
  }
  // A long poll at the current version waits, then answers the same state.
  const auto before = std::chrono::steady_clock::now();
  json same = p.state("?after=" + std::to_string(s["version"].get<int>()));
  EXPECT_GE(std::chrono::steady_clock::now() - before, 9s);
  EXPECT_EQ(same["version"], s["version"]);
  EXPECT_EQ(p.stop(), 0);  // Ctrl-C is how a preview ends
}

// The saved EXR is the image glint render gives at the same spp: the same passes.
TEST(PreviewServer, SaveWritesWhatGlintRenderGivesAtThatSpp) {
  const std::string dir = test::scratchDir("PreviewServer.Save");
  Preview p(dir, "--spp 16");
  ASSERT_GT(p.port(), 0);
  p.waitFor([](const json& s) { return s["rendering"] == false && s["spp"] == 16; });
  auto r = p.client().Post("/api/save?format=exr", "", "text/plain");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json saved = json::parse(r->body);
  EXPECT_EQ(saved["spp"], 16);
  EXPECT_EQ(saved["path"], dir + "/saved/box_preview.exr");
  auto ref = test::runGlint("render " + p.scene() + " --spp 16 --quiet -o " + dir + "/ref.exr");
  ASSERT_EQ(ref.exitCode, 0) << ref.err;
  auto diff = test::runGlint("diff " + dir + "/saved/box_preview.exr " + dir +
                             "/ref.exr --fail 0 --failpercent 0");
  EXPECT_EQ(diff.exitCode, 0) << diff.out << diff.err;
  r = p.client().Post("/api/save?format=png&exposure=1", "", "text/plain");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
  EXPECT_TRUE(fs::exists(dir + "/saved/box_preview.png"));
}

// An edit restarts the render; a bad edit is reported as glint render reports it and keeps
// the image; fixing it restarts again.
TEST(PreviewServer, EditsRestartAndABadEditIsShownAndKeepsTheImage) {
  const std::string dir = test::scratchDir("PreviewServer.Edits");
  Preview p(dir, "--spp 16");
  ASSERT_GT(p.port(), 0);
  json s = p.waitFinished(16);
  const int generation = s["generation"];
  std::string text = test::slurp(p.scene());
  // The red wall turns blue.
  std::string blue = std::regex_replace(text, std::regex(R"("diffuse": \[0.7, 0.12, 0.1\])"),
                                        R"("diffuse": [0.1, 0.12, 0.7])");
  ASSERT_NE(blue, text);
  std::this_thread::sleep_for(1100ms);  // a new modification time even on coarse clocks
  saveAs(p.scene(), blue);
  s = p.waitFor([&](const json& s) {
    return s["generation"].get<int>() > generation && s["rendering"] == false;
  });
  EXPECT_GT(s["generation"].get<int>(), generation);
  EXPECT_EQ(s["spp"], 16);
  EXPECT_TRUE(s["problem"].is_null());

  const auto image = [&] { return p.client().Get("/api/image")->body; };
  const std::string good = image();
  std::this_thread::sleep_for(1100ms);
  saveAs(p.scene(), std::regex_replace(blue, std::regex(R"("radius": 0.35)"), R"("radius": -1)"));
  s = p.waitFor([](const json& s) { return !s["problem"].is_null(); });
  ASSERT_TRUE(s["problem"].is_string());
  EXPECT_EQ(s["problem"], p.scene() + ": /objects/7/radius: must be > 0");
  EXPECT_EQ(image(), good);  // the last good image stays

  const int broken = s["generation"];
  std::this_thread::sleep_for(1100ms);
  saveAs(p.scene(), blue);
  s = p.waitFor([&](const json& s) {
    return s["problem"].is_null() && s["generation"].get<int>() > broken;
  });
  EXPECT_TRUE(s["problem"].is_null());
}

TEST(PreviewServer, TheCameraFollowsThePageAndPrintsAsASidecarBlock) {
  const std::string dir = test::scratchDir("PreviewServer.Camera");
  Preview p(dir, "--spp 8");
  ASSERT_GT(p.port(), 0);
  json s = p.waitFinished(8);
  const int generation = s["generation"];
  auto r = p.client().Post("/api/camera",
                           R"({"position": [0, 1.5, 0.9], "look_at": [0, 0.5, -1],
                               "up": [0, 1, 0], "yfov_degrees": 60})",
                           "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
  s = p.waitFor([&](const json& s) {
    return s["generation"].get<int>() > generation && s["rendering"] == false;
  });
  EXPECT_TRUE(s["custom_camera"].get<bool>());
  EXPECT_EQ(s["camera"]["position"], json({0.0, 1.5, 0.9}));
  EXPECT_EQ(s["camera"]["yfov_degrees"], 60.0);
  auto block = p.client().Get("/api/camera.json");
  ASSERT_TRUE(block);
  const json b = json::parse(block->body);
  EXPECT_EQ(b["cameras"][0]["position"], json({0, 1.5, 0.9}));
  EXPECT_EQ(b["render"]["camera"], "preview");
  // The block is valid sidecar JSON: in the scene in place of its cameras, glint renders it.
  {
    json scene = json::parse(test::slurp(p.scene()));
    scene["cameras"] = b["cameras"];
    scene["render"]["camera"] = b["render"]["camera"];
    std::ofstream(dir + "/view.json") << scene.dump();
    auto r2 = test::runGlint("render " + dir + "/view.json --spp 1 --quiet -o " + dir + "/v.exr");
    EXPECT_EQ(r2.exitCode, 0) << r2.err;
  }
  // Bad cameras are refused, saying what is wrong.
  for (const char* bad : {R"({"position": [0, 1]})", R"(not json)",
                          R"({"position": [0, 1, 2], "look_at": [0, 1, 2]})",
                          R"({"position": [0, 1, 2], "look_at": [0, 0, 0], "yfov_degrees": 0})"}) {
    auto e = p.client().Post("/api/camera", bad, "application/json");
    ASSERT_TRUE(e);
    EXPECT_EQ(e->status, 400) << bad;
    EXPECT_FALSE(e->body.empty());
  }
  r = p.client().Delete("/api/camera");
  ASSERT_TRUE(r);
  s = p.waitFor([](const json& s) { return !s["custom_camera"].get<bool>(); });
  EXPECT_FALSE(s["custom_camera"].get<bool>());
}

TEST(PreviewServer, BadRequestsAndPathsServeNothingFromDisk) {
  const std::string dir = test::scratchDir("PreviewServer.BadPaths");
  std::ofstream(dir + "/secret.txt") << "not for the browser";
  Preview p(dir, "--spp 4");
  ASSERT_GT(p.port(), 0);
  p.waitFor([](const json& s) { return s["spp"] == 4; });
  for (const char* path : {"/box.json", "/secret.txt", "/../secret.txt", "/%2e%2e/secret.txt",
                           "/api/../box.json", "/api/nothing", "/etc/passwd", "/index.html"}) {
    auto r = p.client().Get(path);
    ASSERT_TRUE(r) << path;
    EXPECT_EQ(r->status, 404) << path;
    EXPECT_EQ(r->body.find("not for the browser"), std::string::npos) << path;
  }
  for (const char* query : {"/api/image?aov=depthx", "/api/image?exposure=lots",
                            "/api/image?exposure=1e9", "/api/image?tonemap=reinhard",
                            "/api/image?view=NoSuchView", "/api/state?after=-1"}) {
    auto r = p.client().Get(query);
    ASSERT_TRUE(r) << query;
    EXPECT_EQ(r->status, 400) << query;
    EXPECT_FALSE(r->body.empty()) << query;
  }
  auto r = p.client().Post("/api/save?format=tiff", "", "text/plain");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  r = p.client().Post("/", "x", "text/plain");  // no such method on the page
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 404);
}

// Eight clients at once, and clients that go away mid long poll (a closed tab): every answer
// is whole and the server goes on.
TEST(PreviewServer, ConcurrentClientsAndAClosedTab) {
  const std::string dir = test::scratchDir("PreviewServer.Concurrent");
  Preview p(dir, "--spp 64");
  ASSERT_GT(p.port(), 0);
  p.waitFor([](const json& s) { return s["spp"].get<int>() >= 1; });
  std::atomic<int> good{0}, bad{0};
  std::vector<std::thread> clients;
  for (int c = 0; c < 8; ++c)
    clients.emplace_back([&, c] {
      httplib::Client client("127.0.0.1", p.port());
      client.set_read_timeout(20, 0);
      for (int i = 0; i < 10; ++i) {
        auto r = (i + c) % 2 ? client.Get("/api/image?aov=normal") : client.Get("/api/state");
        const bool ok = r && r->status == 200 &&
                        ((i + c) % 2 ? isPng(r->body) : json::accept(r->body));
        (ok ? good : bad)++;
      }
    });
  // Tabs that close while their long poll waits: the client gives up after 200 ms.
  for (int t = 0; t < 4; ++t) {
    httplib::Client gone("127.0.0.1", p.port());
    gone.set_read_timeout(0, 200000);
    const json s = p.state();
    gone.Get("/api/state?after=" + std::to_string(s["version"].get<int>()));
  }
  for (std::thread& t : clients) t.join();
  EXPECT_EQ(good, 80);
  EXPECT_EQ(bad, 0);
  json s = p.waitFinished(64);
  EXPECT_EQ(s["spp"], 64);  // the render went on
  EXPECT_EQ(p.stop(), 0);
}

// The listening socket is 127.0.0.1's: in the kernel's table, and by trying every other local
// IPv4 address.
TEST(PreviewServer, ListensOnLoopbackOnly) {
  const std::string dir = test::scratchDir("PreviewServer.Loopback");
  Preview p(dir, "--spp 4");
  ASSERT_GT(p.port(), 0);
  // /proc/net/tcp: "sl local_address rem_address st ...", addresses as hex IP:PORT, LISTEN = 0A.
  std::ifstream tcp("/proc/net/tcp");
  std::string line;
  std::getline(tcp, line);
  int listening = 0;
  char wanted[8];
  std::snprintf(wanted, sizeof wanted, "%04X", p.port());
  while (std::getline(tcp, line)) {
    std::istringstream in(line);
    std::string sl, local, remote, state;
    in >> sl >> local >> remote >> state;
    if (state != "0A" || local.substr(local.find(':') + 1) != wanted) continue;
    ++listening;
    EXPECT_EQ(local.substr(0, local.find(':')), "0100007F") << line;  // 127.0.0.1
  }
  EXPECT_EQ(listening, 1);
  std::ifstream tcp6("/proc/net/tcp6");
  std::getline(tcp6, line);
  while (std::getline(tcp6, line)) {
    std::istringstream in(line);
    std::string sl, local, remote, state;
    in >> sl >> local >> remote >> state;
    EXPECT_FALSE(state == "0A" && local.substr(local.find(':') + 1) == wanted) << line;
  }
  ifaddrs* addresses = nullptr;
  ASSERT_EQ(::getifaddrs(&addresses), 0);
  for (ifaddrs* a = addresses; a; a = a->ifa_next) {
    if (!a->ifa_addr || a->ifa_addr->sa_family != AF_INET) continue;
    sockaddr_in to = *reinterpret_cast<sockaddr_in*>(a->ifa_addr);
    if ((ntohl(to.sin_addr.s_addr) >> 24) == 127) continue;
    to.sin_port = htons(uint16_t(p.port()));
    const int s = ::socket(AF_INET, SOCK_STREAM, 0);
    EXPECT_NE(::connect(s, reinterpret_cast<sockaddr*>(&to), sizeof to), 0) << a->ifa_name;
    ::close(s);
  }
  ::freeifaddrs(addresses);
}

TEST(PreviewServer, BadArgumentsExitTwo) {
  const std::string dir = test::scratchDir("PreviewServer.BadArguments");
  auto r = test::runGlint("preview " + dir + "/missing.json");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("missing.json: scene file not found"), std::string::npos) << r.err;
  std::ofstream(dir + "/box.json") << test::cornellBoxJson(8, 1, 1, R"({"type": "path"})");
  r = test::runGlint("preview " + dir + "/box.json --port 70000");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--port"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace glint
