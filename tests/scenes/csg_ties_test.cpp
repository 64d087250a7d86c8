// glint tests — CSG faces that coincide in the author's mind but are stored as different float
// geometry (issue 25, part 1): the three cases found from outside, and a generator of random CSG
// trees whose leaves share faces under random but equivalent transform compositions, written as
// JSON and as .csg (RPN) files; every render is compared with the same solid built from plain
// primitives. Plus the negative control: a real 1e-4 skin still renders as a skin.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "renderer/integrator.h"
#include "renderer/render.h"
#include "scenes/build.h"
#include "scenes/load.h"
#include "test_support.h"

namespace glint {
namespace {

// ---------------------------------------------------------------------------------------------
// Rendering a scene file and comparing two films
// ---------------------------------------------------------------------------------------------

Film renderFile(const std::string& path) {
  SceneDescription d = loadScene(path);
  RenderScene scene = buildRenderScene(d);
  auto integrator = makeIntegrator(scene, d.render);
  RenderStats stats;
  return render(scene, *integrator, d.render, {.threads = 2}, &stats);
}

// Pixels of `a` and `b` that differ by more than `tolerance` in some channel (radiance; the
// scenes below light their surfaces to about 0.1-1).
struct Difference {
  int pixels = 0;         // all differing pixels
  int awayFromEdges = 0;  // ... whose 3x3 neighbourhood in `b` is flat: speckles, not edges
  std::string where;      // the first few of those, "(x, y) a vs b"
};
Difference compareFilms(const Film& a, const Film& b, float tolerance = 0.02f) {
  Difference r;
  auto differ = [&](Rgb x, Rgb y) {
    return std::abs(x.x - y.x) > tolerance || std::abs(x.y - y.y) > tolerance ||
           std::abs(x.z - y.z) > tolerance;
  };
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const Rgb ca = a.color[a.index(x, y)], cb = b.color[b.index(x, y)];
      if (!differ(ca, cb)) continue;
      ++r.pixels;
      bool edge = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= a.width || ny >= a.height) continue;
          edge = edge || differ(cb, b.color[b.index(nx, ny)]);
        }
      if (edge) continue;
      if (++r.awayFromEdges <= 4) {
        char text[96];
        std::snprintf(text, sizeof text, " (%d, %d) %.3f vs %.3f", x, y, double(ca.y),
                      double(cb.y));
        r.where += text;
      }
    }
  return r;
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  ASSERT_TRUE(out.good()) << path;
}

// A scene around `objects` (JSON array items, comma-separated): a floor below y = -1.3, one
// point light, Whitted at 1 spp (the same camera rays for both renders of a comparison).
std::string sceneJson(const std::string& objects, const std::string& camera,
                      const std::string& light, int size = 128) {
  return R"({"render": {"width": )" + std::to_string(size) + R"(, "height": )" +
         std::to_string(size) + R"(, "spp": 1, "seed": 7, "camera": "c",
               "integrator": {"type": "whitted"}, "background": [0.3, 0.35, 0.4]},
  "cameras": [)" +
         camera + R"(],
  "lights": [)" +
         light + R"(],
  "materials": [{"name": "grey", "type": "lambert", "diffuse": [0.6, 0.6, 0.6]}],
  "objects": [{"type": "plane", "point": [0, -1.3, 0], "material": "grey"}, )" +
         objects + "]}";
}

// ---------------------------------------------------------------------------------------------
// The three cases found from outside: A - B with B = [0.5, 1] x [0, 1] x [0, 1] sharing five
// faces with A = [0, 1]^3, A written three different ways
// ---------------------------------------------------------------------------------------------

struct OutsideCase {
  const char* name;
  const char* csg;        // the .csg file
  const char* reference;  // the same solid as a plain box (JSON object)
  // The negative control: the same writing with B 1e-4 short of A on its five shared faces,
  // which leaves A's right half as a 1e-4 skin; and the transform of its plain reference.
  const char* skinCsg;
  const char* skinTransform;
};

const OutsideCase kOutsideCases[] = {
    {"ScaledByAThird",
     "box min 0 0 0 max 3 3 3 scale 0.3333333 0.3333333 0.3333333\n"
     "box min 0.5 0 0 max 1 1 1\n"
     "difference\n",
     R"({"type": "box", "min": [0, 0, 0], "max": [0.5, 1, 1], "material": "grey"})",
     "box min 0 0 0 max 3 3 3 scale 0.3333333 0.3333333 0.3333333\n"
     "box min 0.5 0.0001 0.0001 max 0.9999 0.9999 0.9999\n"
     "difference\n",
     "[]"},
    {"TurnedAndMovedBack",
     "box min 0 0 0 max 1 1 1 rotate 90 0 1 0 translate 0 0 1\n"
     "box min 0.5 0 0 max 1 1 1\n"
     "difference\n",
     R"({"type": "box", "min": [0, 0, 0], "max": [0.5, 1, 1], "material": "grey"})",
     "box min 0 0 0 max 1 1 1 rotate 90 0 1 0 translate 0 0 1\n"
     "box min 0.5 0.0001 0.0001 max 0.9999 0.9999 0.9999\n"
     "difference\n",
     "[]"},
    {"TransformOnTheOperator",
     "box min 0 0 0 max 1 1 1\n"
     "box min 0 0 0 max 1 1 1 scale 0.5 1 1 translate 0.5 0 0\n"
     "difference rotate 30 0 1 0 rotate 20 1 0 0\n",
     R"({"type": "box", "min": [0, 0, 0], "max": [0.5, 1, 1], "material": "grey",
         "transform": [{"rotate": {"axis": [0, 1, 0], "degrees": 30}},
                       {"rotate": {"axis": [1, 0, 0], "degrees": 20}}]})",
     "box min 0 0 0 max 1 1 1\n"
     "box min 0 0.0001 0.0001 max 0.9998 0.9999 0.9999 scale 0.5 1 1 translate 0.5 0 0\n"
     "difference rotate 30 0 1 0 rotate 20 1 0 0\n",
     R"([{"rotate": {"axis": [0, 1, 0], "degrees": 30}}, {"rotate": {"axis": [1, 0, 0], "degrees": 20}}])"},
};

// The three cameras of these cases: the cut face, the shared top and side faces, and a
// grazing view from just above the floor.
const char* const kOutsideCameras[] = {
    R"({"name": "c", "position": [2.2, 1.6, 2.6], "look_at": [0.25, 0.3, 0.5], "yfov_degrees": 45})",
    R"({"name": "c", "position": [-1.5, 2.5, -2.0], "look_at": [0.25, 0.2, 0.5], "yfov_degrees": 45})",
    R"({"name": "c", "position": [3.0, 0.05, 0.5], "look_at": [0.25, 0.5, 0.5], "yfov_degrees": 40})"};
// Low enough to throw the solid's shadow across the floor.
const char* const kOutsideLight =
    R"({"type": "point", "position": [2.5, 3, 1.5], "intensity": 25})";

class CsgOutsideCases : public testing::TestWithParam<OutsideCase> {};

TEST_P(CsgOutsideCases, RenderLikeThePlainBox) {
  const OutsideCase& c = GetParam();
  const std::string dir = test::scratchDir(std::string("csg_ties_") + c.name);
  writeFile(dir + "/solid.csg", c.csg);
  for (const char* camera : kOutsideCameras) {
    writeFile(dir + "/csg.json",
              sceneJson(R"({"type": "csg", "file": "solid.csg", "material": "grey"})", camera,
                        kOutsideLight));
    writeFile(dir + "/plain.json", sceneJson(c.reference, camera, kOutsideLight));
    const Difference d =
        compareFilms(renderFile(dir + "/csg.json"), renderFile(dir + "/plain.json"));
    EXPECT_EQ(d.awayFromEdges, 0) << "camera " << camera << ":" << d.where;
    EXPECT_LE(d.pixels, 2) << "camera " << camera;
  }
}

// The same writings with a real skin: B stops 1e-4 short of A's faces, so A's right half stays
// as five 1e-4 plates (an open box). It must render like those plates as plain boxes, and
// unlike the half box alone.
TEST_P(CsgOutsideCases, ARealSkinStillShows) {
  const OutsideCase& c = GetParam();
  const std::string dir = test::scratchDir(std::string("csg_skin_") + c.name);
  writeFile(dir + "/solid.csg", c.skinCsg);
  const char* boxes[][2] = {{"[0, 0, 0]", "[0.5, 1, 1]"},       // the half A keeps
                            {"[0.5, 0, 0]", "[1, 0.0001, 1]"},  // bottom skin
                            {"[0.5, 0.9999, 0]", "[1, 1, 1]"},  // top
                            {"[0.5, 0, 0]", "[1, 1, 0.0001]"},  // back
                            {"[0.5, 0, 0.9999]", "[1, 1, 1]"},  // front
                            {"[0.9999, 0, 0]", "[1, 1, 1]"}};   // right
  std::string plates;
  for (const auto& b : boxes)
    plates += std::string(plates.empty() ? "" : ", ") + R"({"type": "box", "min": )" + b[0] +
              R"(, "max": )" + b[1] + R"(, "material": "grey", "transform": )" + c.skinTransform +
              "}";
  for (const char* camera : kOutsideCameras) {
    writeFile(dir + "/csg.json",
              sceneJson(R"({"type": "csg", "file": "solid.csg", "material": "grey"})", camera,
                        kOutsideLight));
    writeFile(dir + "/plates.json", sceneJson(plates, camera, kOutsideLight));
    writeFile(dir + "/half.json", sceneJson(c.reference, camera, kOutsideLight));
    const Film csg = renderFile(dir + "/csg.json");
    const Difference d = compareFilms(csg, renderFile(dir + "/plates.json"));
    EXPECT_EQ(d.awayFromEdges, 0) << "camera " << camera << ":" << d.where;
    EXPECT_GT(compareFilms(csg, renderFile(dir + "/half.json")).pixels, 500) << "camera " << camera;
  }
}

INSTANTIATE_TEST_SUITE_P(Issue25, CsgOutsideCases, testing::ValuesIn(kOutsideCases),
                         [](const testing::TestParamInfo<OutsideCase>& param) {
                           return std::string(param.param.name);
                         });

// ---------------------------------------------------------------------------------------------
// The generator
// ---------------------------------------------------------------------------------------------

// Deterministic random numbers (splitmix64; <random>'s distributions differ between standard
// libraries, and a seed must name the same tree everywhere).
class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed * 0x9E3779B97F4A7C15ull + 1) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * 0x1p-53; }
  int below(int n) { return int(next() % uint64_t(n)); }
  bool chance(double p) { return uniform() < p; }
  template <class T, size_t N>
  T pick(const T (&values)[N]) {
    return values[below(int(N))];
  }

 private:
  uint64_t state_;
};

// Numbers as a user types them: seven significant digits. The inverse of a scale by 3 is
// written 0.3333333 and of 0.7 is 1.428571 (3e-7 short: 5 ulps of 1), so the equivalences the
// generator builds hold only to that precision, as they would in a file written by hand.
double userNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.7g", v);
  return std::strtod(text, nullptr);
}
// Numbers a user computes (a box's corners before a scale, a centre turned back): the nearest
// float, written with the nine digits that name it exactly.
double computedNumber(double v) { return double(float(v)); }
std::string num(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

struct V3 {
  double x = 0, y = 0, z = 0;
  double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
V3 userVector(V3 v) { return {userNumber(v.x), userNumber(v.y), userNumber(v.z)}; }
V3 computedVector(V3 v) { return {computedNumber(v.x), computedNumber(v.y), computedNumber(v.z)}; }

// One transform operation, as written in a file (already rounded to what the file says).
struct Op {
  enum Kind { Translate, Rotate, Scale } kind = Translate;
  V3 v;  // translation, scale factors, or rotation axis
  double degrees = 0;

  Op inverse() const {
    switch (kind) {
      case Translate:
        return {Translate, V3{} - v, 0};
      case Rotate:
        return {Rotate, v, -degrees};
      case Scale:
      default:
        return {Scale, userVector({1 / v.x, 1 / v.y, 1 / v.z}), 0};
    }
  }
  // The exact map of what is written (Rodrigues' formula for rotations), in double.
  V3 apply(V3 p) const {
    switch (kind) {
      case Translate:
        return p + v;
      case Scale:
        return {p.x * v.x, p.y * v.y, p.z * v.z};
      case Rotate:
      default: {
        const V3 k = v * (1 / std::sqrt(dot(v, v)));
        const double a = degrees * std::numbers::pi / 180, c = std::cos(a), s = std::sin(a);
        return p * c + cross(k, p) * s + k * (dot(k, p) * (1 - c));
      }
    }
  }
  V3 applyInverse(V3 p) const { return exactInverse().apply(p); }
  Op exactInverse() const {
    return kind == Scale ? Op{Scale, {1 / v.x, 1 / v.y, 1 / v.z}, 0} : inverse();
  }
};

// A CSG node as written: a leaf (box, sphere, cylinder, cone, plane) or an operator.
struct Node {
  std::string type;  // "box", ..., "plane", or "union", "intersection", "difference"
  V3 a, b;           // box min/max; sphere centre; plane point/normal
  double radius = 0, height = 0;
  std::vector<Op> ops;  // applied in order, the first one first
  std::vector<Node> children;

  bool isLeaf() const { return children.empty(); }
};

std::string opsJson(const std::vector<Op>& ops) {
  std::string s = "[";
  for (size_t i = 0; i < ops.size(); ++i) {
    const Op& o = ops[i];
    if (i) s += ", ";
    const std::string v = "[" + num(o.v.x) + ", " + num(o.v.y) + ", " + num(o.v.z) + "]";
    if (o.kind == Op::Translate) s += R"({"translate": )" + v + "}";
    if (o.kind == Op::Scale) s += R"({"scale": )" + v + "}";
    if (o.kind == Op::Rotate)
      s += R"({"rotate": {"axis": )" + v + R"(, "degrees": )" + num(o.degrees) + "}}";
  }
  return s + "]";
}

std::string vec(V3 v) { return "[" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + "]"; }

std::string toJson(const Node& n) {
  std::string s = "{";
  if (n.isLeaf()) {
    s += R"("type": ")" + n.type + "\"";
    if (n.type == "box") s += R"(, "min": )" + vec(n.a) + R"(, "max": )" + vec(n.b);
    if (n.type == "sphere") s += R"(, "center": )" + vec(n.a) + R"(, "radius": )" + num(n.radius);
    if (n.type == "cylinder" || n.type == "cone")
      s += R"(, "radius": )" + num(n.radius) + R"(, "height": )" + num(n.height);
    if (n.type == "plane") s += R"(, "point": )" + vec(n.a) + R"(, "normal": )" + vec(n.b);
  } else {
    s += R"("op": ")" + n.type + R"(", "children": [)";
    for (size_t c = 0; c < n.children.size(); ++c) s += (c ? ", " : "") + toJson(n.children[c]);
    s += "]";
  }
  if (!n.ops.empty()) s += R"(, "transform": )" + opsJson(n.ops);
  return s + "}";
}

std::string opsRpn(const std::vector<Op>& ops) {
  std::string s;
  for (const Op& o : ops) {
    const std::string v = num(o.v.x) + " " + num(o.v.y) + " " + num(o.v.z);
    if (o.kind == Op::Translate) s += " translate " + v;
    if (o.kind == Op::Scale) s += " scale " + v;
    if (o.kind == Op::Rotate) s += " rotate " + num(o.degrees) + " " + v;
  }
  return s;
}

std::string words(V3 v) { return num(v.x) + " " + num(v.y) + " " + num(v.z); }

// Operators are binary in the .csg format: an n-ary node is a left fold, its transform on the
// last operator line.
std::string toRpn(const Node& n) {
  if (n.isLeaf()) {
    std::string s = n.type;
    if (n.type == "box") s += " min " + words(n.a) + " max " + words(n.b);
    if (n.type == "sphere") s += " center " + words(n.a) + " radius " + num(n.radius);
    if (n.type == "cylinder" || n.type == "cone")
      s += " radius " + num(n.radius) + " height " + num(n.height);
    if (n.type == "plane") s += " point " + words(n.a) + " normal " + words(n.b);
    return s + opsRpn(n.ops) + "\n";
  }
  std::string s = toRpn(n.children[0]);
  for (size_t c = 1; c < n.children.size(); ++c) {
    s += toRpn(n.children[c]) + n.type;
    if (c + 1 == n.children.size()) s += opsRpn(n.ops);
    s += "\n";
  }
  return s;
}

// A solid the tree must equal, in tree space, exact: an axis-aligned box, a sphere, or a
// cylinder or cone standing on `base` (axis +Y).
struct Solid {
  enum Kind { Box, Sphere, Cylinder, Cone } kind = Box;
  V3 lo, hi;  // box
  V3 centre;  // sphere centre; cylinder/cone base centre
  double radius = 0, height = 0;
  int thinAxis = -1;  // a thin plate (a box): the axis it is thin along, never split

  bool flatBottom() const { return kind != Sphere; }
};

// The solid as a plain object, placed by `turn` after its own placement, without closing brace.
std::string plainJson(const Solid& s, const std::vector<Op>& turn = {}) {
  std::vector<Op> ops;
  std::string o;
  switch (s.kind) {
    case Solid::Box:
      o = R"({"type": "box", "min": )" + vec(s.lo) + R"(, "max": )" + vec(s.hi);
      break;
    case Solid::Sphere:
      o = R"({"type": "sphere", "center": )" + vec(s.centre) + R"(, "radius": )" + num(s.radius);
      break;
    case Solid::Cylinder:
    case Solid::Cone:
      o = std::string(R"({"type": ")") + (s.kind == Solid::Cone ? "cone" : "cylinder") +
          R"(", "radius": )" + num(s.radius) + R"(, "height": )" + num(s.height);
      ops.push_back({Op::Translate, s.centre, 0});
      break;
  }
  ops.insert(ops.end(), turn.begin(), turn.end());
  if (!ops.empty()) o += R"(, "transform": )" + opsJson(ops);
  return o;
}

// Point membership in double, from what the file says: the generator's own check that a tree
// equals its solid (away from the boundaries, where the files' rounding cannot matter).
V3 undo(const std::vector<Op>& ops, V3 p) {
  for (auto o = ops.rbegin(); o != ops.rend(); ++o) p = o->applyInverse(p);
  return p;
}
bool contains(const Node& n, V3 p) {
  const V3 q = undo(n.ops, p);
  if (n.isLeaf()) {
    if (n.type == "box")
      return q.x >= n.a.x && q.x <= n.b.x && q.y >= n.a.y && q.y <= n.b.y && q.z >= n.a.z &&
             q.z <= n.b.z;
    if (n.type == "sphere") return dot(q - n.a, q - n.a) <= n.radius * n.radius;
    if (n.type == "plane") return dot(q - n.a, n.b) <= 0;
    const double rho = std::sqrt(q.x * q.x + q.z * q.z);
    if (q.y < 0 || q.y > n.height) return false;
    return n.type == "cylinder" ? rho <= n.radius : rho <= n.radius * (1 - q.y / n.height);
  }
  bool in = contains(n.children[0], q);
  for (size_t c = 1; c < n.children.size(); ++c) {
    const bool k = contains(n.children[c], q);
    in = n.type == "union" ? (in || k) : (n.type == "intersection" ? (in && k) : (in && !k));
  }
  return in;
}
bool contains(const Solid& s, V3 p) {
  if (s.kind == Solid::Box)
    return p.x >= s.lo.x && p.x <= s.hi.x && p.y >= s.lo.y && p.y <= s.hi.y && p.z >= s.lo.z &&
           p.z <= s.hi.z;
  const V3 q = p - s.centre;
  if (s.kind == Solid::Sphere) return dot(q, q) <= s.radius * s.radius;
  const double rho = std::sqrt(q.x * q.x + q.z * q.z);
  if (q.y < 0 || q.y > s.height) return false;
  return s.kind == Solid::Cylinder ? rho <= s.radius : rho <= s.radius * (1 - q.y / s.height);
}

// Writes random trees equal to given solids.
class TreeWriter {
 public:
  explicit TreeWriter(uint64_t seed) : rng_(seed) {}
  Rng& rng() { return rng_; }

  // A tree equal to `s`, at most `depth` operators deep (a CSG tree's root must be an
  // operator: `leafAllowed` false).
  Node express(const Solid& s, int depth, bool leafAllowed = true) {
    if (leafAllowed && (depth == 0 || rng_.chance(0.2))) return leaf(s);
    Node n = rewrite(s, depth - 1);
    if (rng_.chance(0.35)) conjugate(&n);
    return n;
  }

  // The node written as G applied after G^-1 on each child: the same solid, with the leaves'
  // transforms composed through the operator's (the third outside case).
  void conjugate(Node* n) {
    const Op g = randomOp();
    n->ops.insert(n->ops.begin(), g);
    for (Node& c : n->children) c.ops.push_back(g.inverse());
  }

  Op randomOp() {
    switch (rng_.below(3)) {
      case 0:
        return {
            Op::Translate,
            userVector({rng_.uniform() * 4 - 2, rng_.uniform() * 4 - 2, rng_.uniform() * 4 - 2}),
            0};
      case 1: {
        V3 axis;
        if (rng_.chance(0.5)) {
          axis[rng_.below(3)] = 1;
        } else {
          axis =
              userVector({rng_.uniform() * 2 - 1, rng_.uniform() * 2 - 1, rng_.uniform() * 2 - 1});
          if (dot(axis, axis) < 0.01) axis = {0, 1, 0};
        }
        const double degrees[] = {90, -90, 180, 30, 45, 60, 120};
        return {Op::Rotate, axis,
                rng_.chance(0.5) ? rng_.pick(degrees) : userNumber(rng_.uniform() * 360 - 180)};
      }
      default: {
        const double factors[] = {2, 0.5, 3, 1.0 / 3, 0.1, 10, 1.5, 0.7};
        return {Op::Scale, userVector({rng_.pick(factors), rng_.pick(factors), rng_.pick(factors)}),
                0};
      }
    }
  }

 private:
  Node op(const char* type, std::vector<Node> children) {
    Node n;
    n.type = type;
    n.children = std::move(children);
    return n;
  }

  // A box that shares the face of `s` on side `face` (axis face/2; upper side when odd) from
  // outside, reaching `depth` beyond it; across the face it matches s or is larger.
  Solid neighbour(const Solid& s, int face, double depth) {
    const int axis = face / 2;
    Solid lo = bounds(s), e = lo;
    for (int i = 0; i < 3; ++i)
      if (i != axis && rng_.chance(0.5)) e.lo[i] -= 0.125 * (1 + rng_.below(3)), e.hi[i] += 0.25;
    if (face & 1)
      e.lo[axis] = lo.hi[axis], e.hi[axis] = lo.hi[axis] + depth;
    else
      e.hi[axis] = lo.lo[axis], e.lo[axis] = lo.lo[axis] - depth;
    return e;
  }

  static Solid bounds(const Solid& s) {
    Solid b;
    if (s.kind == Solid::Box) return s;
    b.lo = {s.centre.x - s.radius, s.centre.y, s.centre.z - s.radius};
    b.hi = {s.centre.x + s.radius, s.centre.y + s.height, s.centre.z + s.radius};
    if (s.kind == Solid::Sphere) b.lo.y = s.centre.y - s.radius, b.hi.y = s.centre.y + s.radius;
    return b;
  }

  // The faces of s that are planes: all six of a box, the caps of a cylinder, a cone's base.
  std::vector<int> flatFaces(const Solid& s) {
    if (s.kind == Solid::Box) return {0, 1, 2, 3, 4, 5};
    if (s.kind == Solid::Cylinder) return {2, 3};
    if (s.kind == Solid::Cone) return {2};
    return {};
  }

  // The half-space on the outside (or inside) of a flat face, as a plane leaf.
  Node halfSpace(const Solid& s, int face, bool outside) {
    const Solid b = bounds(s);
    const int axis = face / 2;
    Node n;
    n.type = "plane";
    n.a = b.lo;
    if (face & 1) n.a = b.hi;
    V3 normal;
    normal[axis] = (face & 1) ? 1 : -1;      // outward
    n.b = outside ? V3{} - normal : normal;  // the solid is behind the normal
    writePlane(&n);
    return n;
  }

  Node rewrite(const Solid& s, int depth) {
    const std::vector<int> faces = flatFaces(s);
    for (;;) {
      switch (rng_.below(7)) {
        case 0:  // A u A
          return op("union", {express(s, depth), express(s, depth)});
        case 1:  // A n A
          return op("intersection", {express(s, depth), express(s, depth)});
        case 2: {  // a box split in two along a lattice plane
          if (s.kind != Solid::Box) break;
          int axis = rng_.below(3);
          if (axis == s.thinAxis) axis = (axis + 1 + rng_.below(2)) % 3;  // a plate splits across
          const double m = s.lo[axis] + (s.hi[axis] - s.lo[axis]) * (1 + rng_.below(3)) / 4;
          Solid a = s, b = s;
          a.hi[axis] = m, b.lo[axis] = m;
          return op("union", {express(a, depth), express(b, depth)});
        }
        case 3: {  // (A u E) - E', E sharing a face of A from outside (the outside cases)
          if (faces.empty()) break;
          const Solid e = neighbour(s, faces[size_t(rng_.below(int(faces.size())))], 0.375);
          return op("difference",
                    {op("union", {express(s, depth), express(e, depth)}), express(e, depth)});
        }
        case 4: {  // A - E, E touching a face of A from outside
          if (faces.empty()) break;
          const Solid e = neighbour(s, faces[size_t(rng_.below(int(faces.size())))], 0.25);
          return op("difference", {express(s, depth), express(e, depth)});
        }
        case 5: {  // A n C, C a box containing A that shares some of its flat faces
          const Solid b = bounds(s);
          Solid c = b;
          for (int f = 0; f < 6; ++f) {
            const bool flat = std::find(faces.begin(), faces.end(), f) != faces.end();
            if (flat && rng_.chance(0.6)) continue;  // shared
            if (f & 1)
              c.hi[f / 2] += 0.125 * (1 + rng_.below(2));
            else
              c.lo[f / 2] -= 0.125 * (1 + rng_.below(2));
          }
          return op("intersection", {express(s, depth), express(c, depth)});
        }
        case 6: {  // A minus the half-space beyond a face, or A n the half-space behind it
          if (faces.empty()) break;
          const int face = faces[size_t(rng_.below(int(faces.size())))];
          if (rng_.chance(0.5))
            return op("difference", {express(s, depth), halfSpace(s, face, true)});
          return op("intersection", {express(s, depth), halfSpace(s, face, false)});
        }
        default:
          break;
      }
    }
  }

  // A leaf equal to s, written through a random chain of equivalent transforms.
  Node leaf(const Solid& s) {
    Node n;
    switch (s.kind) {
      case Solid::Box:
        n.type = "box", n.a = s.lo, n.b = s.hi;
        break;
      case Solid::Sphere:
        n.type = "sphere", n.a = s.centre, n.radius = s.radius;
        break;
      case Solid::Cylinder:
      case Solid::Cone:
        n.type = s.kind == Solid::Cone ? "cone" : "cylinder";
        n.radius = s.radius, n.height = s.height;
        n.ops.push_back({Op::Translate, s.centre, 0});
        break;
    }
    const int preimages = rng_.below(3);
    for (int i = 0; i < preimages; ++i) preimage(&n);
    // G, G^-1 pairs anywhere in the chain.
    const int pairs = rng_.below(3);
    for (int i = 0; i < pairs; ++i) {
      const Op g = randomOp();
      const size_t at = size_t(rng_.below(int(n.ops.size()) + 1));
      n.ops.insert(n.ops.begin() + std::ptrdiff_t(at), {g, g.inverse()});
    }
    return n;
  }

  void writePlane(Node* n) {
    const int preimages = rng_.below(3);
    for (int i = 0; i < preimages; ++i) {
      // Write the plane's point and normal as the preimage of a rotation or a translation.
      const Op g = rng_.chance(0.5) ? randomRotation() : randomTranslation();
      n->a = computedVector(g.applyInverse(n->a));
      if (g.kind == Op::Rotate) n->b = computedVector(g.applyInverse(n->b));
      n->ops.insert(n->ops.begin(), g);
    }
  }

  Op randomRotation() {
    Op g = randomOp();
    while (g.kind != Op::Rotate) g = randomOp();
    return g;
  }
  Op randomTranslation() {
    return {Op::Translate,
            userVector({rng_.uniform() * 2 - 1, rng_.uniform() * 2 - 1, rng_.uniform() * 2 - 1}),
            0};
  }

  // The leaf's parameters replaced by their preimage under an operation G put first in its
  // chain: the solid is unchanged, its numbers are not (a box scaled by 3 and written a third
  // as large; a sphere turned and its centre turned back; a cylinder stretched along its axis).
  void preimage(Node* n) {
    Op g;
    if (n->type == "box") {
      switch (rng_.below(3)) {
        case 0:
          g = randomTranslation();
          break;
        case 1: {  // a quarter turn: the box stays axis-aligned
          V3 axis;
          axis[rng_.below(3)] = 1;
          const double degrees[] = {90, -90, 180};
          g = {Op::Rotate, axis, rng_.pick(degrees)};
          break;
        }
        default: {
          const double factors[] = {2, 0.5, 3, 1.0 / 3, 0.1, 10};
          g = {Op::Scale, userVector({rng_.pick(factors), rng_.pick(factors), rng_.pick(factors)}),
               0};
        }
      }
      V3 a = g.applyInverse(n->a), b = g.applyInverse(n->b);
      for (int i = 0; i < 3; ++i) {
        if (a[i] > b[i]) std::swap(a[i], b[i]);
        // A quarter turn back lands within 1e-16 of the lattice, as a user would write it.
        if (g.kind == Op::Rotate)
          a[i] = std::round(a[i] * 1e9) / 1e9, b[i] = std::round(b[i] * 1e9) / 1e9;
      }
      n->a = computedVector(a), n->b = computedVector(b);
    } else if (n->type == "sphere") {
      if (rng_.chance(0.5)) {
        const double factors[] = {2, 0.5, 3, 1.0 / 3, 0.1, 10};
        const double f = userNumber(rng_.pick(factors));
        g = {Op::Scale, {f, f, f}, 0};
        n->radius = computedNumber(n->radius / f);
      } else {
        g = rng_.chance(0.5) ? randomRotation() : randomTranslation();
      }
      n->a = computedVector(g.applyInverse(n->a));
    } else {  // cylinder, cone: about their own axis, before their placement
      if (rng_.chance(0.5)) {
        const double across[] = {2, 0.5, 3, 1.0 / 3}, along[] = {2, 0.5, 3, 1.0 / 3, 0.1, 10};
        const double f = userNumber(rng_.pick(across)), h = userNumber(rng_.pick(along));
        g = {Op::Scale, {f, h, f}, 0};
        n->radius = computedNumber(n->radius / f);
        n->height = computedNumber(n->height / h);
      } else {
        g = {Op::Rotate, {0, 1, 0}, userNumber(rng_.uniform() * 360 - 180)};
      }
    }
    n->ops.insert(n->ops.begin(), g);
  }

  Rng rng_;
};

// The thicknesses of the thin plates, as fractions of the trees' size (2.6, the width of the
// region the solids stand in): 4e-5 of it is 1.04e-4, some 30 times the leaves' tolerances.
constexpr double kThinWalls[] = {4e-5, 2e-4, 1e-3};
constexpr double kTreeSize = 2.6;

// 1 or 2 solids on a lattice of 1/8, side by side, in [-1.3, 1.3] x [-1, 1] x [-0.8, 0.8].
// `thin`: one of them may be a thin plate instead, a box one of kThinWalls thick along a random
// axis, its faces on the lattice and that far from it.
std::vector<Solid> randomSolids(Rng& rng, bool thin = false) {
  std::vector<Solid> solids;
  const int count = 1 + rng.below(2);
  for (int i = 0; i < count; ++i) {
    const double cx = count == 1 ? 0 : (i == 0 ? -0.7 : 0.7);
    const double half = count == 1 ? 1.0 : 0.5;  // half-width of the cell along x
    auto lattice = [&](double lo, double hi) {
      return lo + 0.125 * rng.below(int(std::lround((hi - lo) / 0.125)) + 1);
    };
    Solid s;
    s.kind = Solid::Kind(rng.below(4));
    if (s.kind == Solid::Box) {
      s.lo = {lattice(cx - half, cx - 0.125), lattice(-1, -0.25), lattice(-0.75, -0.125)};
      s.hi = {lattice(cx + 0.125, cx + half), lattice(0, 0.75), lattice(0.125, 0.75)};
    } else {
      s.radius = lattice(0.25, half);
      s.centre = {cx, lattice(-1, -0.25), 0};
      s.height = lattice(0.5, 1.5);
      if (s.kind == Solid::Sphere) s.centre.y = lattice(-0.75, 0);
    }
    if (thin && i == 0 && rng.chance(0.6)) {
      s = Solid{};
      s.lo = {lattice(cx - half, cx - 0.125), lattice(-1, -0.25), lattice(-0.75, -0.125)};
      s.hi = {lattice(cx + 0.125, cx + half), lattice(0, 0.75), lattice(0.125, 0.75)};
      s.thinAxis = rng.below(3);
      s.hi[s.thinAxis] = s.lo[s.thinAxis] + rng.pick(kThinWalls) * kTreeSize;
    }
    solids.push_back(s);
  }
  return solids;
}

// One random scene: the tree (as a JSON node), and the plain objects it must render like.
struct GeneratedScene {
  std::vector<Solid> solids;
  Node tree;
  std::vector<Op> turn;      // the root's last operation, shared with the plain objects
  std::string plainObjects;  // JSON array items
  std::string camera, light;
  std::string grazing;  // the grazing view, for messages ("axis 1, 4 degrees"; empty: none)
};

// `thinAndGrazing`: the solids may hold a thin plate (randomSolids), and the camera looks 4 or 1
// degrees above the planes of one axis of the tree's frame, turned with the tree (nearly in the
// plane of its faces along that axis, shared ones included). Without it the trees and views of
// the first generator test, seed for seed.
GeneratedScene generate(uint64_t seed, bool thinAndGrazing = false) {
  TreeWriter writer(seed);
  Rng& rng = writer.rng();
  GeneratedScene g;
  g.solids = randomSolids(rng, thinAndGrazing);
  const std::vector<Solid>& solids = g.solids;
  std::vector<Node> parts;
  for (const Solid& s : solids) parts.push_back(writer.express(s, 3, solids.size() > 1));
  if (parts.size() == 1) {
    g.tree = std::move(parts[0]);
  } else {
    g.tree.type = "union";
    g.tree.children = std::move(parts);
  }
  // Half the trees are turned as a whole by their root node: every shared face then lies
  // off the axes in tree space, its leaves' matrices composed through the root's.
  std::vector<Op>& turn = g.turn;
  if (rng.chance(0.5)) {
    const Op r = writer.randomOp();
    if (r.kind == Op::Rotate) {
      g.tree.ops.push_back(r);
      turn.push_back(r);
    }
  }
  for (const Solid& s : solids) {
    if (!g.plainObjects.empty()) g.plainObjects += ", ";
    g.plainObjects += plainJson(s, turn) + R"(, "material": "grey"})";
  }
  const double azimuth = rng.uniform() * 2 * std::numbers::pi;
  const double distance = 4.5;
  V3 eye;
  if (thinAndGrazing) {
    // Grazing: along the plane of axis k of the tree's frame, 4 or 1 degrees out of it.
    const int k = rng.below(3);
    const double degrees = rng.chance(0.5) ? 4 : 1;
    V3 n, u, v;
    n[k] = 1, u[(k + 1) % 3] = 1, v[(k + 2) % 3] = 1;
    const double a = degrees * std::numbers::pi / 180;
    V3 dir = (u * std::cos(azimuth) + v * std::sin(azimuth)) * std::cos(a) + n * std::sin(a);
    for (const Op& o : g.turn) dir = o.apply(dir);
    // Above the floor (y = -1.3): the other side of the plane, the same angle, when not.
    if (-0.2 + distance * dir.y < -1.0) dir = V3{} - dir;
    eye = V3{0, -0.2, 0} + dir * distance;
    g.grazing = "axis " + std::to_string(k) + ", " + num(degrees) + " degrees";
  } else {
    const double elevation =
        (rng.chance(0.2) ? 2 : 10 + rng.uniform() * 60) * std::numbers::pi / 180;
    eye = {distance * std::cos(elevation) * std::cos(azimuth), distance * std::sin(elevation),
           distance * std::cos(elevation) * std::sin(azimuth)};
  }
  g.camera = R"({"name": "c", "position": )" + vec(eye) +
             R"(, "look_at": [0, -0.2, 0], "yfov_degrees": 45})";
  const double la = rng.uniform() * 2 * std::numbers::pi;
  g.light = R"({"type": "point", "position": )" +
            vec({3 * std::cos(la), 2.5 + rng.uniform() * 2, 3 * std::sin(la)}) +
            R"(, "intensity": 40})";
  return g;
}

int countLeaves(const Node& n) {
  int c = n.isLeaf() ? 1 : 0;
  for (const Node& k : n.children) c += countLeaves(k);
  return c;
}

// What one generated scene gave: differing pixels of each file form against the plain solids,
// and the CSG render (JSON form) for further comparisons.
struct SeedResult {
  bool valid = false;  // the generator's own check that the tree is its solids passed
  Difference forms[2];
  Film csg;
};

// Checks that the tree of `g` is its solids (100,000 points in double), writes the tree as a
// .csg file and the three scenes (plain solids, the tree as JSON, the tree from the file) into
// `dir`, renders them and compares each form with the plain solids.
SeedResult runSeed(const GeneratedScene& g, uint64_t seed, const std::string& dir) {
  SeedResult r;
  // The tree is the solids (without the root's turn, which the plain objects share).
  Node unturned = g.tree;
  if (!g.turn.empty()) unturned.ops.pop_back();
  Rng points(seed);
  int wrong = 0;
  V3 example;
  for (int i = 0; i < 100000; ++i) {
    const V3 p{points.uniform() * 3.4 - 1.7, points.uniform() * 2.6 - 1.6,
               points.uniform() * 2.4 - 1.2};
    bool inSolids = false;
    for (const Solid& s : g.solids) inSolids = inSolids || contains(s, p);
    if (contains(unturned, p) != inSolids) ++wrong, example = p;
  }
  if (wrong != 0) {
    ADD_FAILURE() << "seed " << seed << ": the generator's tree is not its solid at (" << example.x
                  << ", " << example.y << ", " << example.z << "):\n"
                  << toRpn(g.tree);
    return r;
  }
  std::filesystem::create_directories(dir);
  writeFile(dir + "/tree.csg", toRpn(g.tree));
  writeFile(dir + "/plain.json", sceneJson(g.plainObjects, g.camera, g.light));
  writeFile(dir + "/json.json",
            sceneJson(R"({"type": "csg", "material": "grey", "tree": )" + toJson(g.tree) + "}",
                      g.camera, g.light));
  writeFile(
      dir + "/rpn.json",
      sceneJson(R"({"type": "csg", "material": "grey", "file": "tree.csg"})", g.camera, g.light));
  const Film plain = renderFile(dir + "/plain.json");
  r.csg = renderFile(dir + "/json.json");
  r.forms[0] = compareFilms(r.csg, plain);
  r.forms[1] = compareFilms(renderFile(dir + "/rpn.json"), plain);
  r.valid = true;
  return r;
}

// Each seed's tree in both file forms against the plain solids. Zero speckles: no differing
// pixel away from the reference's own edges, over every seed; at most a few edge pixels in all
// (a camera ray within 1e-7 of a silhouette may fall either side of two float representations).
TEST(CsgGenerator, RandomTreesWithSharedFacesRenderLikeThePlainSolids) {
  const std::string root = test::scratchDir("csg_generator");
  // GLINT_CSG_SEEDS=1000 (and a gtest filter) hunts longer; a failing seed's files stay in
  // test_output/csg_generator/seedN.
  const char* seeds = std::getenv("GLINT_CSG_SEEDS");
  const int kSeeds = seeds ? std::max(1, std::atoi(seeds)) : 60;
  int edgePixels = 0, leaves = 0;
  for (uint64_t seed = 1; seed <= uint64_t(kSeeds); ++seed) {
    const GeneratedScene g = generate(seed);
    leaves += countLeaves(g.tree);
    const SeedResult r = runSeed(g, seed, root + "/seed" + std::to_string(seed));
    ASSERT_TRUE(r.valid);
    for (int f = 0; f < 2; ++f) {
      const Difference& d = r.forms[f];
      EXPECT_EQ(d.awayFromEdges, 0)
          << "seed " << seed << " (" << (f ? "rpn" : "json") << ")" << d.where << ", tree:\n"
          << toRpn(g.tree);
      edgePixels += d.pixels - d.awayFromEdges;
    }
  }
  RecordProperty("edge_pixels", edgePixels);
  RecordProperty("leaves", leaves);
  std::printf("[ csg generator ] %d seeds, %d leaves, %d differing edge pixels in %d renders\n",
              kSeeds, leaves, edgePixels, 2 * kSeeds);
  EXPECT_LE(edgePixels, 2 * kSeeds / 10);
}

// Issue 49, item 4 (the invariance net's CSG rewriting part): the generator again, with thin
// plates among the solids (4e-5, 2e-4 or 1e-3 of the trees' size thick, written through the
// same random equivalent transforms, shared faces and all) and every view grazing: 4 or 1 degrees
// out of the planes of one axis of the tree's frame, turned with the tree. Zero speckles, a few
// silhouette pixels at most, as for the first test. GLINT_CSG_SEEDS hunts longer here too.
//
// The control: the same renders against the plain solids without their plate must differ, by
// many pixels for most seeds (a plate seen edge-on, or hidden behind the other solid, may
// show on a few pixels only): the comparison would see a lost wall.
TEST(CsgGenerator, ThinWallsAndGrazingViewsRenderLikeThePlainSolids) {
  const std::string root = test::scratchDir("csg_generator_thin");
  const char* seeds = std::getenv("GLINT_CSG_SEEDS");
  const int kSeeds = seeds ? std::max(1, std::atoi(seeds)) : 40;
  int edgePixels = 0, leaves = 0, plates = 0, platesSeen = 0;
  for (uint64_t seed = 1; seed <= uint64_t(kSeeds); ++seed) {
    const GeneratedScene g = generate(seed, true);
    leaves += countLeaves(g.tree);
    const std::string dir = root + "/seed" + std::to_string(seed);
    const SeedResult r = runSeed(g, seed, dir);
    ASSERT_TRUE(r.valid);
    for (int f = 0; f < 2; ++f) {
      const Difference& d = r.forms[f];
      EXPECT_EQ(d.awayFromEdges, 0) << "seed " << seed << " (" << (f ? "rpn" : "json") << ", "
                                    << g.grazing << ")" << d.where << ", tree:\n"
                                    << toRpn(g.tree);
      edgePixels += d.pixels - d.awayFromEdges;
    }
    // The control: the solids without the plate.
    std::string others;
    bool plate = false;
    for (const Solid& s : g.solids) {
      if (s.thinAxis >= 0) {
        plate = true;
        continue;
      }
      others += std::string(others.empty() ? "" : ", ") + plainJson(s, g.turn) +
                R"(, "material": "grey"})";
    }
    if (!plate) continue;
    ++plates;
    if (others.empty()) others = R"({"type": "sphere", "radius": 0.01, "center": [0, 5, 9]})";
    writeFile(dir + "/without_plate.json", sceneJson(others, g.camera, g.light));
    const int lost = compareFilms(r.csg, renderFile(dir + "/without_plate.json")).pixels;
    platesSeen += lost > 20;
  }
  RecordProperty("edge_pixels", edgePixels);
  RecordProperty("leaves", leaves);
  std::printf(
      "[ csg generator ] thin walls, grazing views: %d seeds, %d leaves, %d differing edge "
      "pixels in %d renders; %d plates, %d of them differ by more than 20 pixels from "
      "the solids without them\n",
      kSeeds, leaves, edgePixels, 2 * kSeeds, plates, platesSeen);
  EXPECT_LE(edgePixels, 2 * kSeeds / 10);
  EXPECT_GT(plates, 0);
  EXPECT_GE(2 * platesSeen, plates) << "the plates should show in most views";
}

// The negative control: a plate 1e-4 thick (a box minus all of it but a skin), written through
// the same kind of equivalent transforms, still renders as the plate. Removing it would leave
// nothing: the comparison with the plain plate would fail on thousands of pixels.
TEST(CsgGenerator, ARealThinSkinStillRendersAsASkin) {
  const std::string dir = test::scratchDir("csg_thin_skin");
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    TreeWriter writer(seed);
    Solid a, cut;
    a.lo = {-0.75, -0.75, -0.5}, a.hi = {0.75, 0.25, 0.5};
    cut.lo = {-1, -1, -0.5 + 1e-4}, cut.hi = {1, 1, 1};  // leaves z in [-0.5, -0.4999]
    Node tree;
    tree.type = "difference";
    tree.children = {writer.express(a, 1), writer.express(cut, 1)};
    writer.conjugate(&tree);
    Solid plate = a;
    plate.hi.z = -0.5 + 1e-4;
    const std::string camera =
        R"({"name": "c", "position": [1.2, 1.5, -4], "look_at": [0, -0.3, -0.5], "yfov_degrees": 40})";
    const std::string light = R"({"type": "point", "position": [1, 3, -3], "intensity": 40})";
    writeFile(dir + "/tree.csg", toRpn(tree));
    writeFile(
        dir + "/csg.json",
        sceneJson(R"({"type": "csg", "material": "grey", "file": "tree.csg"})", camera, light));
    writeFile(dir + "/plain.json",
              sceneJson(plainJson(plate) + R"(, "material": "grey"})", camera, light));
    writeFile(
        dir + "/empty.json",
        sceneJson(R"({"type": "sphere", "radius": 0.01, "center": [0, 5, 9]})", camera, light));
    const Film csg = renderFile(dir + "/csg.json");
    const Difference d = compareFilms(csg, renderFile(dir + "/plain.json"));
    EXPECT_EQ(d.awayFromEdges, 0) << "seed " << seed << ":\n" << toRpn(tree);
    // And the plate is really there: without it the image differs on many pixels.
    EXPECT_GT(compareFilms(csg, renderFile(dir + "/empty.json")).pixels, 2000) << "seed " << seed;
  }
}

// ---------------------------------------------------------------------------------------------
// Issue 49, item 3: shared faces seen at grazing angles
// ---------------------------------------------------------------------------------------------

// Trees whose leaves share faces, each equal to one plain box: A - B with B flush against four of
// A's faces, the union of two halves sharing the face x = 0.5 (and four coplanar ones), A n C
// with C flush against four of A's faces; the leaves in the same frame, or one of them written
// another way (as the outside cases: scaled by 0.3333333, turned a quarter and moved back, B
// scaled and moved into place).
struct GrazingTree {
  const char* name;
  const char* csg;  // the tree as a .csg file, without the whole tree's turn
  const char* lo;   // the plain box it equals
  const char* hi;
};

const GrazingTree kGrazingTrees[] = {
    {"DifferenceSameFrame", "box min 0 0 0 max 1 1 1\nbox min 0.5 0 0 max 1 1 1\ndifference",
     "[0, 0, 0]", "[0.5, 1, 1]"},
    {"DifferenceScaledByAThird",
     "box min 0 0 0 max 3 3 3 scale 0.3333333 0.3333333 0.3333333\nbox min 0.5 0 0 max 1 1 "
     "1\ndifference",
     "[0, 0, 0]", "[0.5, 1, 1]"},
    {"DifferenceTurnedAndMovedBack",
     "box min 0 0 0 max 1 1 1 rotate 90 0 1 0 translate 0 0 1\nbox min 0.5 0 0 max 1 1 "
     "1\ndifference",
     "[0, 0, 0]", "[0.5, 1, 1]"},
    {"DifferenceScaledCut",
     "box min 0 0 0 max 1 1 1\nbox min 0 0 0 max 1 1 1 scale 0.5 1 1 translate 0.5 0 0\ndifference",
     "[0, 0, 0]", "[0.5, 1, 1]"},
    {"UnionSameFrame", "box min 0 0 0 max 0.5 1 1\nbox min 0.5 0 0 max 1 1 1\nunion", "[0, 0, 0]",
     "[1, 1, 1]"},
    {"UnionScaledByAThird",
     "box min 0 0 0 max 1.5 3 3 scale 0.3333333 0.3333333 0.3333333\nbox min 0.5 0 0 max 1 1 "
     "1\nunion",
     "[0, 0, 0]", "[1, 1, 1]"},
    {"IntersectionSameFrame", "box min 0 0 0 max 1 1 1\nbox min -0.5 0 0 max 0.5 1 1\nintersection",
     "[0, 0, 0]", "[0.5, 1, 1]"},
    {"IntersectionScaledByAThird",
     "box min 0 0 0 max 3 3 3 scale 0.3333333 0.3333333 0.3333333\nbox min -0.5 0 0 max 0.5 1 "
     "1\nintersection",
     "[0, 0, 0]", "[0.5, 1, 1]"},
};

// The whole tree turned (or not): the plain box gets the same turn.
const std::vector<Op> kGrazingTurn = {{Op::Rotate, {0, 1, 0}, 30}, {Op::Rotate, {1, 0, 0}, 20}};

struct GrazingView {
  V3 eye, target, up;
  bool inSeamPlane = false;  // the eye in the plane x = 0.5: the middle column looks along it
  double fov = 0;
  std::string name;
};

// Views 4 and 1 degrees out of the planes of the trees' faces (x, y and z = 0 and 1: all of
// them shared by two leaves, or coplanar with a face of the other leaf), from 3 units away,
// looking at the face's centre (on the plane x = 0.5 for the y and z faces: the union's seam,
// the difference's cut, the intersection's new face):
//  * for the y and z faces, twice from within the plane x = 0.5, along the face, with an 8 degree
//    field of view: the middle column of pixels then looks along that plane, onto the seam or
//    edge, every ray there within a float step of the plane; and twice from other directions,
//    once from the far side of the face's plane (-4 or -1 degrees), with 40 degrees;
//  * for the x faces, from four directions around the face's normal, two of them from the far
//    side of its plane, with 8 and 40 degrees.
// `all` (GLINT_CSG_GRAZING_VIEWS=all, a longer hunt): 16 directions, both sides of the plane and
// both fields of view for every face and angle.
std::vector<GrazingView> grazingViews(bool all) {
  struct Direction {
    double phi, fov, side;  // azimuth in the face's plane, field of view, +1 or -1: which side
  };
  const double pi = std::numbers::pi;
  std::vector<GrazingView> views;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      std::vector<Direction> directions;
      if (all) {
        for (int k = 0; k < 16; ++k)
          for (double fov : {8.0, 40.0})
            for (double sign : {1.0, -1.0}) directions.push_back({k * pi / 8, fov, sign});
      } else if (axis == 0) {
        directions = {
            {0.1, 8, 1}, {0.1 + pi / 2, 40, -1}, {0.1 + pi, 8, -1}, {0.1 + 1.5 * pi, 40, 1}};
      } else {
        directions = {{0, 8, 1}, {pi, 8, 1}, {0.8, 40, 1}, {0.8 + pi, 40, -1}};
      }
      V3 n, target{0.5, 0.5, 0.5}, along, across;
      n[axis] = side ? 1 : -1;
      target[axis] = side;
      if (axis == 0) {
        along = {0, 1, 0}, across = {0, 0, 1};
      } else {
        along[axis == 1 ? 2 : 1] = 1;  // in the face and in the plane x = 0.5
        across = {1, 0, 0};
      }
      for (double degrees : {4.0, 1.0})
        for (const Direction& d : directions) {
          const double a = d.side * degrees * pi / 180;
          const V3 inFace = along * std::cos(d.phi) + across * std::sin(d.phi);
          GrazingView v;
          v.target = target;
          v.eye = target + (inFace * std::cos(a) + n * std::sin(a)) * 3;
          v.up = n;
          v.fov = d.fov;
          v.inSeamPlane = axis != 0 && (d.phi == 0 || d.phi == pi);
          v.name = std::string("face ") + "xyz"[axis] + " = " + std::to_string(side) + ", " +
                   num(d.side * degrees) + " degrees, azimuth " + num(d.phi) + ", fov " +
                   num(d.fov);
          views.push_back(v);
        }
    }
  return views;
}

// Pixels of `a` and `b` that differ by more than 0.02 in some channel, outside column `skip`.
int differingOutsideColumn(const Film& a, const Film& b, int skip) {
  int n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      if (x == skip) continue;
      const Rgb ca = a.color[a.index(x, y)], cb = b.color[b.index(x, y)];
      n += std::abs(ca.x - cb.x) > 0.02f || std::abs(ca.y - cb.y) > 0.02f ||
           std::abs(ca.z - cb.z) > 0.02f;
    }
  return n;
}

// A scene for the grazing views: 97 x 97 pixels (the middle column looks along the plane
// x = 0.5), one sample at each pixel's centre (a box filter 1e-4 pixels wide: the camera rays
// are the ones a pixel-centre render traces, so a speckle does not hide in a pixel's average).
std::string grazingSceneJson(const std::string& object, const GrazingView& v,
                             const std::vector<Op>& turn) {
  V3 eye = v.eye, target = v.target, up = v.up;
  for (const Op& o : turn) eye = o.apply(eye), target = o.apply(target), up = o.apply(up);
  const std::string camera = R"({"name": "c", "position": )" + vec(eye) + R"(, "look_at": )" +
                             vec(target) + R"(, "up": )" + vec(up) + R"(, "yfov_degrees": )" +
                             num(v.fov) + "}";
  std::string scene = sceneJson(
      object, camera, R"({"type": "point", "position": [2.5, 3, 1.5], "intensity": 25})", 97);
  const std::string filter = R"("spp": 1,)";
  scene.replace(scene.find(filter), filter.size(),
                R"("spp": 1, "filter": {"type": "box", "radius": 0.0001},)");
  return scene;
}

class CsgGrazingViews : public testing::TestWithParam<std::tuple<GrazingTree, bool>> {};

// Every grazing view of the tree renders like the plain box: no speckle (a pixel that differs
// where the plain box's image is flat around it), and at most one differing pixel on an edge a
// view on average (a ray within the leaves' tolerance of an edge may fall either side), besides
// the middle column of the views from within the plane x = 0.5: rays along the cut or new face
// of a difference or intersection, which is seen edge-on there, may fall either side of it.
//
// Before the fix (at a150da7) the unions failed: 14 speckles in UnionSameFrame, 21 in
// UnionSameFrameTurned, 6 in UnionScaledByAThird, 28 in UnionScaledByAThirdTurned, lines of
// them down the middle column: the seam face of one half, shaded black or dark, bounded the
// union where a ray entered the outer face at the seam (or ran along the seam, between halves
// 5e-8 apart as written). A pixel-centre hunt over 6,144 grazing views at 256 x 256 found 13
// speckles, on the unions and on DifferenceTurnedAndMovedBackTurned: slivers of A's corner
// floating in the air where B, flush against that corner, was missed by rounding. Each render's
// images and scenes of a failing view stay in test_output/csg_grazing_TREE/.
TEST_P(CsgGrazingViews, RenderLikeThePlainBox) {
  const auto& [tree, turned] = GetParam();
  const std::vector<Op> turn = turned ? kGrazingTurn : std::vector<Op>{};
  const std::string dir =
      test::scratchDir(std::string("csg_grazing_") + tree.name + (turned ? "_turned" : ""));
  writeFile(dir + "/tree.csg", std::string(tree.csg) + opsRpn(turn) + "\n");
  const std::string plain = std::string(R"({"type": "box", "min": )") + tree.lo + R"(, "max": )" +
                            tree.hi + R"(, "material": "grey", "transform": )" + opsJson(turn) +
                            "}";
  const char* csgObject = R"({"type": "csg", "file": "tree.csg", "material": "grey"})";
  const char* all = std::getenv("GLINT_CSG_GRAZING_VIEWS");
  int speckles = 0, edges = 0, alongSeam = 0, views = 0;
  for (const GrazingView& v : grazingViews(all && std::string(all) == "all")) {
    ++views;
    writeFile(dir + "/csg.json", grazingSceneJson(csgObject, v, turn));
    writeFile(dir + "/plain.json", grazingSceneJson(plain, v, turn));
    const Film csg = renderFile(dir + "/csg.json"), box = renderFile(dir + "/plain.json");
    const Difference d = compareFilms(csg, box);
    const int outside = v.inSeamPlane ? differingOutsideColumn(csg, box, csg.width / 2) : d.pixels;
    speckles += d.awayFromEdges;
    const int column = d.pixels - outside;  // differing pixels in the middle column
    edges += std::max(0, d.pixels - d.awayFromEdges - column);
    alongSeam += column;
    if (d.awayFromEdges > 0) {
      const std::string stem = dir + "/view" + std::to_string(views);
      writeFile(stem + "_csg.json", grazingSceneJson(csgObject, v, turn));
      writeFile(stem + "_plain.json", grazingSceneJson(plain, v, turn));
      writeImage(stem + "_csg.png", csg, RenderSettings{}, ImageMetadata{});
      writeImage(stem + "_plain.png", box, RenderSettings{}, ImageMetadata{});
      ADD_FAILURE() << tree.name << (turned ? " turned" : "") << ", " << v.name << ": "
                    << d.awayFromEdges << " speckles:" << d.where
                    << "\n  scenes and images: " << stem << "_{csg,plain}.{json,png}";
    }
  }
  std::printf(
      "[ csg grazing ] %s%s: %d views, %d speckles, %d differing edge pixels (%d more on "
      "the plane x = 0.5 seen edge-on)\n",
      tree.name, turned ? " turned" : "", views, speckles, edges, alongSeam);
  EXPECT_LE(edges, views) << "at most one differing edge pixel a view on average";
}

INSTANTIATE_TEST_SUITE_P(Issue49, CsgGrazingViews,
                         testing::Combine(testing::ValuesIn(kGrazingTrees), testing::Bool()),
                         [](const testing::TestParamInfo<std::tuple<GrazingTree, bool>>& p) {
                           return std::string(std::get<0>(p.param).name) +
                                  (std::get<1>(p.param) ? "Turned" : "");
                         });

}  // namespace
}  // namespace glint
