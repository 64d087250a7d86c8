// Tests for `glint preview`'s HTTP side (docs/preview.md), with a plain client (cpp-httplib's):
// the state and image answers, restarts on edits and camera changes, a bad edit's message, the
// saved EXR against glint render, bad requests, no file served from disk, concurrent clients,
// a client that goes away, a socket bound to loopback only, and who may ask: the Host, the
// Origin of a change and the run's token. The page itself is tested in Chromium
// (tests/browser).
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
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
    pid_ =
        test::startGlint("preview " + scene_ + " --port 0 --output-dir " + dir + "/saved " + extra,
                         dir + "/out.log", dir + "/err.log");
    // The first line on stdout is the address, with the run's token (checked by
    // TheAddressCarriesANewTokenEachRun; taken as it is here).
    const std::regex address(R"(glint: preview at http://127\.0\.0\.1:(\d+)/(\?token=(\S*))?\n)");
    for (int i = 0; i < 200 && port_ == 0; ++i) {
      std::smatch m;
      const std::string out = test::slurp(dir + "/out.log");
      if (std::regex_search(out, m, address)) {
        port_ = std::stoi(m[1]);
        token_ = m[3];
      } else {
        std::this_thread::sleep_for(50ms);
      }
    }
  }
  ~Preview() {
    if (pid_ > 0) stop();  // never kill(-1): that signals every process we may
  }
  int port() const { return port_; }
  const std::string& token() const { return token_; }
  int stop() {  // Ctrl-C: its exit code
    if (pid_ <= 0) return -1;
    ::kill(pid_t(pid_), SIGINT);
    const int code = test::waitGlint(pid_);
    pid_ = -1;
    return code;
  }
  const std::string& scene() const { return scene_; }
  // A client as the page is: every request carries the token in X-Glint-Token.
  httplib::Client client() const {
    httplib::Client c = anonymous();
    c.set_default_headers({{"X-Glint-Token", token_}});
    return c;
  }
  // A client without the token.
  httplib::Client anonymous() const {
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
    return waitFor([spp](const json& st) {
      return st["generation"].get<int>() >= 1 && st["spp"] == spp && st["rendering"] == false;
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
  std::string dir_, scene_, token_;
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

// An answer to a request written byte for byte (cpp-httplib's client writes a Host of its own).
struct RawAnswer {
  int status = 0;  // 0: no answer
  std::string head, body;
};

// Sends `head` (the request line and headers, each ending in \r\n) then `body`, asking the
// server to close the connection after its answer.
RawAnswer rawRequest(int port, const std::string& head, const std::string& body = "") {
  RawAnswer answer;
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(uint16_t(port));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  timeval timeout{20, 0};
  ::setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  if (::connect(s, reinterpret_cast<sockaddr*>(&to), sizeof to) != 0) {
    ::close(s);
    return answer;
  }
  const std::string request =
      head + "Connection: close\r\nContent-Length: " + std::to_string(body.size()) + "\r\n\r\n" +
      body;
  for (size_t sent = 0; sent < request.size();) {
    const ssize_t n = ::send(s, request.data() + sent, request.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) break;
    sent += size_t(n);
  }
  std::string text;
  char buffer[4096];
  for (ssize_t n; (n = ::recv(s, buffer, sizeof buffer, 0)) > 0;) text.append(buffer, size_t(n));
  ::close(s);
  const size_t end = text.find("\r\n\r\n");
  if (text.rfind("HTTP/1.", 0) != 0 || end == std::string::npos) return answer;
  answer.status = std::atoi(text.c_str() + 9);
  answer.head = text.substr(0, end);
  answer.body = text.substr(end + 4);
  return answer;
}

TEST(PreviewServer, RefinesPassByPassAndServesTheImage) {
  const std::string dir = test::scratchDir("PreviewServer.Refines");
  Preview p(dir, "--spp 32");
  ASSERT_GT(p.port(), 0) << test::slurp(dir + "/err.log");
  json s = p.waitFor([](const json& st) { return st["spp"] == 32 && st["rendering"] == false; });
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
  p.waitFor([](const json& st) { return st["rendering"] == false && st["spp"] == 16; });
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
  s = p.waitFor([&](const json& st) {
    return st["generation"].get<int>() > generation && st["rendering"] == false;
  });
  EXPECT_GT(s["generation"].get<int>(), generation);
  EXPECT_EQ(s["spp"], 16);
  EXPECT_TRUE(s["problem"].is_null());

  const auto image = [&] { return p.client().Get("/api/image")->body; };
  const std::string good = image();
  std::this_thread::sleep_for(1100ms);
  saveAs(p.scene(), std::regex_replace(blue, std::regex(R"("radius": 0.35)"), R"("radius": -1)"));
  s = p.waitFor([](const json& st) { return !st["problem"].is_null(); });
  ASSERT_TRUE(s["problem"].is_string());
  EXPECT_EQ(s["problem"], p.scene() + ": /objects/7/radius: must be > 0");
  EXPECT_EQ(image(), good);  // the last good image stays

  const int broken = s["generation"];
  std::this_thread::sleep_for(1100ms);
  saveAs(p.scene(), blue);
  s = p.waitFor([&](const json& st) {
    return st["problem"].is_null() && st["generation"].get<int>() > broken;
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
  s = p.waitFor([&](const json& st) {
    return st["generation"].get<int>() > generation && st["rendering"] == false;
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
  s = p.waitFor([](const json& st) { return !st["custom_camera"].get<bool>(); });
  EXPECT_FALSE(s["custom_camera"].get<bool>());
}

TEST(PreviewServer, BadRequestsAndPathsServeNothingFromDisk) {
  const std::string dir = test::scratchDir("PreviewServer.BadPaths");
  std::ofstream(dir + "/secret.txt") << "not for the browser";
  Preview p(dir, "--spp 4");
  ASSERT_GT(p.port(), 0);
  p.waitFor([](const json& st) { return st["spp"] == 4; });
  for (const char* path : {"/box.json", "/secret.txt", "/../secret.txt", "/%2e%2e/secret.txt",
                           "/api/../box.json", "/api/nothing", "/etc/passwd", "/index.html"}) {
    auto r = p.client().Get(path);
    ASSERT_TRUE(r) << path;
    EXPECT_EQ(r->status, 404) << path;
    EXPECT_EQ(r->body.find("not for the browser"), std::string::npos) << path;
  }
  for (const char* query :
       {"/api/image?aov=depthx", "/api/image?exposure=lots", "/api/image?exposure=1e9",
        "/api/image?tonemap=reinhard", "/api/image?view=NoSuchView", "/api/state?after=-1"}) {
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
  p.waitFor([](const json& st) { return st["spp"].get<int>() >= 1; });
  std::atomic<int> good{0}, bad{0};
  std::vector<std::thread> clients;
  for (int c = 0; c < 8; ++c)
    clients.emplace_back([&, c] {
      httplib::Client client = p.client();
      for (int i = 0; i < 10; ++i) {
        auto r = (i + c) % 2 ? client.Get("/api/image?aov=normal") : client.Get("/api/state");
        const bool ok =
            r && r->status == 200 && ((i + c) % 2 ? isPng(r->body) : json::accept(r->body));
        (ok ? good : bad)++;
      }
    });
  // Tabs that close while their long poll waits: the client gives up after 200 ms.
  for (int t = 0; t < 4; ++t) {
    httplib::Client gone = p.client();
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

// ---- Who may ask (docs/preview.md): any web page in the user's browser can reach 127.0.0.1 ----

// The printed address carries a token of 256 bits, new each run.
TEST(PreviewServer, TheAddressCarriesANewTokenEachRun) {
  const std::string dir = test::scratchDir("PreviewServer.Token");
  std::string tokens[2];
  for (int run = 0; run < 2; ++run) {
    const std::string runDir = dir + "/" + std::to_string(run);
    fs::create_directories(runDir);
    Preview p(runDir, "--spp 1");
    ASSERT_GT(p.port(), 0) << test::slurp(runDir + "/err.log");
    const std::string out = test::slurp(runDir + "/out.log");
    const std::string first = out.substr(0, out.find('\n'));
    EXPECT_TRUE(std::regex_match(
        first, std::regex(R"(glint: preview at http://127\.0\.0\.1:\d+/\?token=[0-9a-f]{64})")))
        << first;
    tokens[run] = p.token();
  }
  EXPECT_EQ(tokens[0].size(), 64u);
  EXPECT_NE(tokens[0], tokens[1]);
}

// DNS rebinding: a page of another name that resolves to 127.0.0.1 sends its own name as Host.
// Only the loopback names with this port are answered, whatever the token.
TEST(PreviewServer, RefusesAHostThatIsNotThisServer) {
  const std::string dir = test::scratchDir("PreviewServer.Host");
  Preview p(dir, "--spp 4");
  ASSERT_GT(p.port(), 0);
  p.waitFor([](const json& st) { return st["spp"] == 4; });
  const std::string port = std::to_string(p.port());
  const std::string other = std::to_string(p.port() == 65535 ? 1 : p.port() + 1);
  const std::string token = "X-Glint-Token: " + p.token() + "\r\n";
  for (const std::string& host : std::vector<std::string>{
           "evil.example:" + port, "evil.example", "127.0.0.1:" + other, "localhost:" + other,
           "[::1]:" + other, "127.0.0.1", "localhost", "127.0.0.1.evil.example:" + port,
           "localhost.evil.example:" + port, "0.0.0.0:" + port, "127.0.0.2:" + port,
           "127.0.0.1:" + port + ".evil.example", "127.0.0.1:0" + port, std::string()}) {
    for (const std::string& path : std::vector<std::string>{"/api/state", "/?token=" + p.token()}) {
      const RawAnswer a =
          rawRequest(p.port(), "GET " + path + " HTTP/1.1\r\nHost: " + host + "\r\n" + token);
      EXPECT_EQ(a.status, 403) << host << " " << path;
      EXPECT_EQ(a.body.find("\"version\""), std::string::npos) << host;  // no state
      EXPECT_EQ(a.body.find("<html"), std::string::npos) << host;        // no page
      EXPECT_NE(a.body.find("Host"), std::string::npos) << host << ": " << a.body;
      EXPECT_EQ(a.body.find(p.token()), std::string::npos) << host;
    }
  }
  // No Host at all, and a second Host after a good one.
  RawAnswer a = rawRequest(p.port(), "GET /api/state HTTP/1.1\r\n" + token);
  EXPECT_EQ(a.status, 403);
  a = rawRequest(p.port(), "GET /api/state HTTP/1.1\r\nHost: 127.0.0.1:" + port +
                               "\r\nHost: evil.example:" + port + "\r\n" + token);
  EXPECT_EQ(a.status, 403);
  // A refused change changes nothing.
  a = rawRequest(p.port(),
                 "POST /api/camera HTTP/1.1\r\nHost: evil.example:" + port + "\r\n" + token,
                 R"({"position": [0, 1.5, 0.9], "look_at": [0, 0.5, -1]})");
  EXPECT_EQ(a.status, 403);
  // The loopback names with this port are answered (a host name in any case).
  for (const std::string& host : std::vector<std::string>{"127.0.0.1:" + port, "localhost:" + port,
                                                          "LocalHost:" + port, "[::1]:" + port}) {
    a = rawRequest(p.port(), "GET /api/state HTTP/1.1\r\nHost: " + host + "\r\n" + token);
    EXPECT_EQ(a.status, 200) << host << ": " << a.body;
    EXPECT_TRUE(json::accept(a.body) && json::parse(a.body).contains("version")) << host;
  }
  a = rawRequest(p.port(),
                 "GET /?token=" + p.token() + " HTTP/1.1\r\nHost: localhost:" + port + "\r\n");
  EXPECT_EQ(a.status, 200);
  EXPECT_NE(a.body.find("<html"), std::string::npos);
  EXPECT_FALSE(p.state()["custom_camera"].get<bool>());
}

// A request that changes something and says it comes from another origin is refused, even with
// the token; the page's own origins are answered.
TEST(PreviewServer, RefusesChangesFromAnotherOrigin) {
  const std::string dir = test::scratchDir("PreviewServer.Origin");
  Preview p(dir, "--spp 8");
  ASSERT_GT(p.port(), 0);
  const json s0 = p.waitFinished(8);
  const std::string port = std::to_string(p.port());
  const std::string camera = R"({"position": [0, 1.5, 0.9], "look_at": [0, 0.5, -1]})";
  for (const std::string& origin :
       {std::string("http://evil.example"), "http://evil.example:" + port, std::string("null"),
        "http://127.0.0.1:" + std::to_string(p.port() == 65535 ? 1 : p.port() + 1),
        "https://127.0.0.1:" + port, "http://127.0.0.1:" + port + ".evil.example",
        "http://localhost:" + port + "/"}) {
    const httplib::Headers from{{"Origin", origin}};
    auto r = p.client().Post("/api/camera", from, camera, "application/json");
    ASSERT_TRUE(r) << origin;
    EXPECT_EQ(r->status, 403) << origin;
    EXPECT_NE(r->body.find("another web page"), std::string::npos) << origin << ": " << r->body;
    r = p.client().Post("/api/camera", from, camera, "text/plain");  // a "simple" request
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 403) << origin;
    r = p.client().Delete("/api/camera", from);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 403) << origin;
    r = p.client().Post("/api/save?format=exr", from, "", "text/plain");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 403) << origin;
  }
  EXPECT_FALSE(fs::exists(dir + "/saved/box_preview.exr"));
  std::this_thread::sleep_for(300ms);
  json s = p.state();
  EXPECT_EQ(s["generation"], s0["generation"]);  // nothing restarted
  EXPECT_FALSE(s["custom_camera"].get<bool>());
  EXPECT_EQ(s["camera"], s0["camera"]);
  // Reading with the token is no change: a browser keeps the answer from another origin's page
  // (no Access-Control-Allow-Origin is ever sent).
  auto r = p.client().Get("/api/state", {{"Origin", "http://evil.example"}});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_FALSE(r->has_header("Access-Control-Allow-Origin"));
  // The page's own origins, and tools that send no Origin, may change the camera.
  r = p.client().Post("/api/camera", {{"Origin", "http://localhost:" + port}}, camera,
                      "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
  s = p.waitFor([](const json& now) { return now["custom_camera"].get<bool>(); });
  EXPECT_TRUE(s["custom_camera"].get<bool>());
  r = p.client().Delete("/api/camera", {{"Origin", "http://127.0.0.1:" + port}});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
  s = p.waitFor([](const json& now) { return !now["custom_camera"].get<bool>(); });
  EXPECT_FALSE(s["custom_camera"].get<bool>());
  r = p.client().Post("/api/save?format=exr", "", "text/plain");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
}

// Every request carries the run's token: the page's address has it in its query, the page
// sends it in X-Glint-Token. A refusal is a short 403 that never shows the token, and the token
// is printed once, in the address.
TEST(PreviewServer, EveryRequestNeedsTheRunsToken) {
  const std::string dir = test::scratchDir("PreviewServer.NeedsToken");
  Preview p(dir, "--spp 8");
  ASSERT_GT(p.port(), 0);
  const json s0 = p.waitFinished(8);
  const std::string token = p.token();
  const std::string wrong = token.substr(0, 63) + (token.ends_with('0') ? "1" : "0");
  const std::string camera = R"({"position": [0, 1.5, 0.9], "look_at": [0, 0.5, -1]})";
  const auto refused = [&](const httplib::Result& r, const std::string& what) {
    ASSERT_TRUE(r) << what;
    EXPECT_EQ(r->status, 403) << what;
    EXPECT_NE(r->body.find("token"), std::string::npos) << what << ": " << r->body;
    EXPECT_LT(r->body.size(), 120u) << what << ": " << r->body;
    EXPECT_EQ(r->body.find(token), std::string::npos) << what;
    EXPECT_EQ(r->body.find("<html"), std::string::npos) << what;
    EXPECT_FALSE(isPng(r->body)) << what;
  };
  // No token, a wrong one, a part of it, more than it, in the header or the query.
  std::vector<std::pair<std::string, httplib::Headers>> askers = {{"", {}}};
  for (const std::string& bad :
       {wrong, token.substr(0, 32), token + "0", std::string(), std::string(64, '0')}) {
    askers.push_back({"", {{"X-Glint-Token", bad}}});
    askers.push_back({"token=" + bad, {}});
  }
  askers.push_back({"token=" + token, {{"X-Glint-Token", wrong}}});  // the header is what counts
  for (const auto& [query, headers] : askers) {
    const std::string q = query.empty() ? "" : "?" + query;
    const std::string what = q + (headers.empty() ? "" : " header " + headers.begin()->second);
    httplib::Client c = p.anonymous();
    refused(c.Get("/" + q, headers), "GET /" + what);
    refused(c.Get("/api/state" + q, headers), "GET /api/state" + what);
    refused(c.Get("/api/image" + q, headers), "GET /api/image" + what);
    refused(c.Get("/api/camera.json" + q, headers), "GET /api/camera.json" + what);
    refused(c.Post("/api/camera" + q, headers, camera, "application/json"), "POST camera" + what);
    refused(c.Delete("/api/camera" + q, headers), "DELETE camera" + what);
    refused(c.Post("/api/save" + (q.empty() ? "?format=exr" : q + "&format=exr"), headers, "",
                   "text/plain"),
            "POST save" + what);
  }
  EXPECT_FALSE(fs::exists(dir + "/saved/box_preview.exr"));
  std::this_thread::sleep_for(300ms);
  json s = p.state();
  EXPECT_EQ(s["generation"], s0["generation"]);
  EXPECT_FALSE(s["custom_camera"].get<bool>());

  // The token in the query or in the header opens everything.
  auto r = p.anonymous().Get("/?token=" + token);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_NE(r->body.find("<html"), std::string::npos);
  r = p.anonymous().Get("/api/state?token=" + token);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(json::parse(r->body)["version"], s["version"]);
  r = p.anonymous().Get("/api/image?aov=beauty", {{"X-Glint-Token", token}});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_TRUE(isPng(r->body));
  r = p.anonymous().Post("/api/camera", {{"X-Glint-Token", token}}, camera, "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
  s = p.waitFor([](const json& now) { return now["custom_camera"].get<bool>(); });
  EXPECT_TRUE(s["custom_camera"].get<bool>());
  EXPECT_EQ(p.stop(), 0);
  // The token is in the printed address and nowhere else in the output.
  const std::string out = test::slurp(dir + "/out.log"), err = test::slurp(dir + "/err.log");
  EXPECT_EQ(out.find(token), out.find("?token=") + 7);
  EXPECT_EQ(out.find(token, out.find(token) + 1), std::string::npos) << out;
  EXPECT_EQ(err.find(token), std::string::npos) << err;
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
