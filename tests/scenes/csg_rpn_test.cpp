// glint tests — the reverse-polish .csg format: tree structure, shapes, transforms, and every
// error with its file:line.
#include "scenes/csg_rpn.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <set>
#include <string>

#include "geometry/shapes/box.h"
#include "geometry/shapes/cone.h"
#include "geometry/shapes/cylinder.h"
#include "geometry/shapes/plane.h"
#include "geometry/shapes/sphere.h"
#include "scene_error_support.h"
#include "test_support.h"

namespace glint {
namespace {

using test::errorFrom;

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

constexpr const char* kFile = "tree.csg";

CsgTreeDesc parse(const std::string& text) { return parseCsgRpn(text, kFile); }

SceneError parseError(const std::string& text) {
  return errorFrom([&] { parse(text); });
}

// what() starts with "tree.csg:LINE: " and the message contains `phrase`.
#define EXPECT_CSG_ERROR(text, line, phrase)                                      \
  do {                                                                            \
    SceneError e_ = parseError(text);                                             \
    std::string prefix_ = std::string(kFile) + ":" + std::to_string(line) + ": "; \
    EXPECT_EQ(std::string(e_.what()).rfind(prefix_, 0), 0u) << e_.what();         \
    EXPECT_EQ(e_.where().file, std::string(kFile) + ":" + std::to_string(line));  \
    EXPECT_EQ(e_.where().pointer, "");                                            \
    EXPECT_NE(e_.message().find(phrase), std::string::npos) << e_.what();         \
  } while (0)

void expectNear(Vec3f a, Vec3f b, float tolerance = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

void expectSameTransform(const Transform& a, const Transform& b) {
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(a.matrix().m[r][c], b.matrix().m[r][c], 1e-6f);
}

// ---------------------------------------------------------------------------------------------
// Valid files
// ---------------------------------------------------------------------------------------------

TEST(CsgRpn, ParsesOperatorsIntoATreeWithLeftAndRightChildren) {
  CsgTreeDesc tree = parse(
      "# a lens drilled through, with a cone on top\n"
      "sphere center -0.5 0 0 radius 1 material glass\n"
      "sphere radius 1 center 0.5 0 0\n"
      "intersection\n"
      "cylinder height 2 radius 0.25 rotate 90 1 0 0 translate 0 0 -1 material steel\n"
      "difference\n"
      "cone radius 0.5 height 1\n"
      "union translate 0 2 0\n");
  ASSERT_EQ(tree.nodes.size(), 7u);
  EXPECT_EQ(tree.root, 6);

  const CsgNodeDesc& lensLeft = tree.nodes[0];
  EXPECT_EQ(lensLeft.op, CsgOp::Leaf);
  EXPECT_STREQ(lensLeft.shape->typeName(), "sphere");
  EXPECT_EQ(test::shapeAs<Sphere>(lensLeft.shape).center(), (Vec3f{-0.5f, 0, 0}));
  EXPECT_EQ(test::shapeAs<Sphere>(lensLeft.shape).radius(), 1);
  EXPECT_EQ(lensLeft.materialName, "glass");
  EXPECT_EQ(lensLeft.material, -1);
  EXPECT_TRUE(lensLeft.children.empty());
  EXPECT_TRUE(lensLeft.parentFromNode.isIdentity());
  EXPECT_EQ(lensLeft.where.file, "tree.csg:2");
  EXPECT_EQ(lensLeft.where.pointer, "");

  EXPECT_EQ(test::shapeAs<Sphere>(tree.nodes[1].shape).center(),
            (Vec3f{0.5f, 0, 0}));  // keys in any order
  EXPECT_EQ(tree.nodes[1].materialName, "");

  EXPECT_EQ(tree.nodes[2].op, CsgOp::Intersection);
  EXPECT_EQ(tree.nodes[2].children, (std::vector<int>{0, 1}));
  EXPECT_EQ(tree.nodes[2].where.file, "tree.csg:4");

  const CsgNodeDesc& drill = tree.nodes[3];
  EXPECT_STREQ(drill.shape->typeName(), "cylinder");
  EXPECT_EQ(test::shapeAs<Cylinder>(drill.shape).radius(), 0.25f);
  EXPECT_EQ(test::shapeAs<Cylinder>(drill.shape).height(), 2);
  EXPECT_TRUE(test::shapeAs<Cylinder>(drill.shape).capped());
  EXPECT_EQ(drill.materialName, "steel");
  expectSameTransform(drill.parentFromNode,
                      Transform::translate({0, 0, -1}) * Transform::rotate(90, {1, 0, 0}));

  EXPECT_EQ(tree.nodes[4].op, CsgOp::Difference);
  EXPECT_EQ(tree.nodes[4].children, (std::vector<int>{2, 3}));  // lens minus drill

  EXPECT_STREQ(tree.nodes[5].shape->typeName(), "cone");
  EXPECT_EQ(test::shapeAs<Cone>(tree.nodes[5].shape).radius(), 0.5f);
  EXPECT_EQ(test::shapeAs<Cone>(tree.nodes[5].shape).height(), 1);
  EXPECT_TRUE(test::shapeAs<Cone>(tree.nodes[5].shape).capped());

  const CsgNodeDesc& root = tree.nodes[6];
  EXPECT_EQ(root.op, CsgOp::Union);
  EXPECT_EQ(root.children, (std::vector<int>{4, 5}));
  EXPECT_EQ(root.parentFromNode, Transform::translate({0, 2, 0}));
  EXPECT_EQ(root.where.file, "tree.csg:8");
}

TEST(CsgRpn, ParsesBoxAndPlane) {
  CsgTreeDesc tree = parse(
      "box max 1 2 3 min -1 -2 -3\n"
      "plane normal 0 2 0 point 0 0.5 0\n"
      "intersection\n");
  ASSERT_EQ(tree.nodes.size(), 3u);
  EXPECT_STREQ(tree.nodes[0].shape->typeName(), "box");
  EXPECT_EQ(test::shapeAs<Box>(tree.nodes[0].shape).lower(), (Vec3f{-1, -2, -3}));
  EXPECT_EQ(test::shapeAs<Box>(tree.nodes[0].shape).upper(), (Vec3f{1, 2, 3}));
  EXPECT_STREQ(tree.nodes[1].shape->typeName(), "plane");
  EXPECT_EQ(test::shapeAs<Plane>(tree.nodes[1].shape).point(), (Vec3f{0, 0.5f, 0}));
  EXPECT_EQ(test::shapeAs<Plane>(tree.nodes[1].shape).normal(), (Vec3f{0, 1, 0}));  // normalized
  EXPECT_EQ(tree.root, 2);
}

TEST(CsgRpn, SinglePrimitiveIsTheRoot) {
  CsgTreeDesc tree = parse("sphere center 1 2 3 radius 4\n");
  ASSERT_EQ(tree.nodes.size(), 1u);
  EXPECT_EQ(tree.root, 0);
}

TEST(CsgRpn, TransformsApplyInTheOrderWritten) {
  // Scale first, then translate: the origin lands on (1, 0, 0) and (1, 0, 0) on (3, 0, 0).
  CsgTreeDesc scaleFirst = parse("sphere center 0 0 0 radius 1 scale 2 2 2 translate 1 0 0");
  const Transform& a = scaleFirst.nodes[0].parentFromNode;
  expectNear(a.point({0, 0, 0}), {1, 0, 0});
  expectNear(a.point({1, 0, 0}), {3, 0, 0});
  CsgTreeDesc translateFirst = parse("sphere translate 1 0 0 scale 2 2 2 center 0 0 0 radius 1");
  const Transform& b = translateFirst.nodes[0].parentFromNode;
  expectNear(b.point({0, 0, 0}), {2, 0, 0});
  expectNear(b.point({1, 0, 0}), {4, 0, 0});
  // Rotation: right-handed about the axis, in degrees.
  CsgTreeDesc rotated = parse("sphere center 0 0 0 radius 1 rotate 90 0 1 0");
  expectNear(rotated.nodes[0].parentFromNode.point({1, 0, 0}), {0, 0, -1});
}

TEST(CsgRpn, ShearFollowsTheDocumentedLayout) {
  CsgTreeDesc tree = parse("box min 0 0 0 max 1 1 1 shear 1 2 3 4 5 6");
  const Transform& t = tree.nodes[0].parentFromNode;
  // x' = x + XY y + XZ z, y' = YX x + y + YZ z, z' = ZX x + ZY y + z.
  expectNear(t.point({1, 0, 0}), {1, 3, 5});
  expectNear(t.point({0, 1, 0}), {1, 1, 6});
  expectNear(t.point({0, 0, 1}), {2, 4, 1});
  expectNear(t.inverse().point(t.point({0.3f, -0.7f, 2})), {0.3f, -0.7f, 2}, 1e-4f);
}

TEST(CsgRpn, ReadsDecimalNumberForms) {
  CsgTreeDesc tree = parse("sphere center +1.5 -.25 2e-3 radius 1 scale 1E2 .5 3.\n");
  EXPECT_EQ(test::shapeAs<Sphere>(tree.nodes[0].shape).center(), (Vec3f{1.5f, -0.25f, 0.002f}));
  // 1e-999 underflows to (near) zero: finite, so only the radius check rejects it.
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius 1e-999\n", 1, "'radius' must be > 0");
  expectNear(tree.nodes[0].parentFromNode.point({1, 1, 1}), {100, 0.5f, 3});
}

TEST(CsgRpn, IgnoresCommentsBlankLinesAndSpacing) {
  CsgTreeDesc tree = parse(
      "# header comment\n"
      "\n"
      "   \t  \n"
      "\tsphere   center 0 0 0\tradius 1   # trailing comment\r\n"
      "# between\n"
      "sphere center +1 0 0 radius 1e0#no space before the comment\n"
      "  union  \r\n"
      "# trailing comment without a newline");
  ASSERT_EQ(tree.nodes.size(), 3u);
  EXPECT_EQ(tree.nodes[0].where.file, "tree.csg:4");
  EXPECT_EQ(tree.nodes[1].where.file, "tree.csg:6");
  EXPECT_EQ(test::shapeAs<Sphere>(tree.nodes[1].shape).center(), (Vec3f{1, 0, 0}));
  EXPECT_EQ(tree.nodes[2].where.file, "tree.csg:7");
  EXPECT_EQ(tree.nodes[2].op, CsgOp::Union);
}

// ---------------------------------------------------------------------------------------------
// Errors: each at its file:line
// ---------------------------------------------------------------------------------------------

TEST(CsgRpn, StackUnderflowSaysHowManyOperandsThereAre) {
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius 1\n\n# one is not enough\nunion\n", 4,
                   "stack underflow: 'union' needs 2 operands, the stack holds 1");
  EXPECT_CSG_ERROR("difference\n", 1, "the stack holds 0");
}

TEST(CsgRpn, LeftoverOperandsNameTheFirstUnconsumedLine) {
  EXPECT_CSG_ERROR(
      "# three spheres, one union\n"
      "sphere center 0 0 0 radius 1\n"
      "sphere center 1 0 0 radius 1\n"
      "sphere center 2 0 0 radius 1\n"
      "union\n",
      2, "leftover operands: 2 nodes remain");
  EXPECT_CSG_ERROR("box min 0 0 0 max 1 1 1\nbox min 0 0 0 max 2 2 2\n", 1,
                   "first unconsumed one is on line 1");
}

TEST(CsgRpn, EmptyFileIsAnError) {
  EXPECT_CSG_ERROR("", 1, "empty CSG file");
  EXPECT_CSG_ERROR("# nothing but comments\n\n", 2, "empty CSG file");
}

TEST(CsgRpn, UnknownWordsAreQuoted) {
  EXPECT_CSG_ERROR("\nspehre center 0 0 0 radius 1\n", 2,
                   "unknown token 'spehre'; did you mean 'sphere'?");
  EXPECT_CSG_ERROR("torus\n", 1, "unknown token 'torus'");
  EXPECT_CSG_ERROR("sphere centre 0 0 0 radius 1\n", 1,
                   "unknown key 'centre' for 'sphere'; did you mean 'center'?");
  EXPECT_CSG_ERROR("box min 0 0 0 max 1 1 1 radius 2\n", 1, "unknown key 'radius' for 'box'");
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius 1\nsphere center 0 0 0 radius 1\nunion twist 3\n", 3,
                   "unknown key 'twist' for 'union'");
}

TEST(CsgRpn, MissingKeysAreErrors) {
  EXPECT_CSG_ERROR("sphere center 0 0 0\n", 1, "'sphere' needs 'radius'");
  EXPECT_CSG_ERROR("box min 0 0 0\n", 1, "'box' needs 'max'");
  EXPECT_CSG_ERROR("cylinder radius 1\n", 1, "'cylinder' needs 'height'");
  EXPECT_CSG_ERROR("cone height 1\n", 1, "'cone' needs 'radius'");
  EXPECT_CSG_ERROR("plane point 0 0 0\n", 1, "'plane' needs 'normal'");
}

TEST(CsgRpn, KeysGivenTwiceAreErrors) {
  EXPECT_CSG_ERROR("sphere radius 1 center 0 0 0 radius 2\n", 1, "'radius' given twice");
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius 1 material a material b\n", 1,
                   "'material' given twice");
}

TEST(CsgRpn, BadNumbersAreErrors) {
  EXPECT_CSG_ERROR("sphere center 0 x 0 radius 1\n", 1,
                   "expected a number after 'center', got 'x'");
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius 1.5.2\n", 1, "got '1.5.2'");
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius nan\n", 1, "'radius': 'nan' is not a finite number");
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius inf\n", 1, "'inf' is not a finite number");
  EXPECT_CSG_ERROR("sphere center 0 0 -infinity radius 1\n", 1, "not a finite number");
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius 1e39\n", 1, "'1e39' is not a finite number");
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius 1e999\n", 1, "'1e999' is not a finite number");
}

TEST(CsgRpn, TooFewOrTooManyNumbersAreErrors) {
  EXPECT_CSG_ERROR("sphere center 0 0 radius 1\n", 1, "'center' needs 3 numbers, got 2");
  EXPECT_CSG_ERROR("sphere radius 1 center 0\n", 1, "'center' needs 3 numbers, got 1");
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius\n", 1, "'radius' needs 1 number, got 0");
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius 1 rotate 90 0 1\n", 1,
                   "'rotate' needs 4 numbers, got 3");
  EXPECT_CSG_ERROR("box min 0 0 0 max 1 1 1 shear 1 2 3 4 5\n", 1,
                   "'shear' needs 6 numbers, got 5");
  EXPECT_CSG_ERROR("sphere center 0 0 0 0 radius 1\n", 1, "unexpected number '0' after 'center'");
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius 1 material\n", 1, "'material' needs a name");
}

TEST(CsgRpn, SizesMustBePositive) {
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius 0\n", 1, "'radius' must be > 0, got 0");
  EXPECT_CSG_ERROR("cylinder radius 1 height -2\n", 1, "'height' must be > 0, got -2");
  EXPECT_CSG_ERROR("cone radius -1 height 1\n", 1, "'radius' must be > 0, got -1");
  EXPECT_CSG_ERROR("box min 0 0 0 max 1 0 1\n", 1,
                   "box 'max' must be greater than 'min' in every component");
  EXPECT_CSG_ERROR("box min 0 0 0 max 1 1 -1\n", 1, "min (0, 0, 0), max (1, 1, -1)");
}

TEST(CsgRpn, DegenerateDirectionsAreErrors) {
  EXPECT_CSG_ERROR("plane point 0 0 0 normal 0 0 0\n", 1, "plane 'normal' must not be zero");
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius 1 rotate 30 0 0 0\n", 1,
                   "the rotation axis must not be zero");
}

TEST(CsgRpn, SingularTransformsAreErrors) {
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius 1 scale 1 0 1\n", 1,
                   "'scale': factors must not be zero");
  EXPECT_CSG_ERROR("box min 0 0 0 max 1 1 1 shear 1 0 1 0 0 0\n", 1,
                   "the shear matrix is singular");
  // Each step is fine; together they underflow (or overflow) a float.
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius 1 scale 1e-20 1 1 scale 1e-20 1 1\n", 1,
                   "the composed transform is singular");
  EXPECT_CSG_ERROR("sphere center 0 0 0 radius 1 scale 1e30 1 1 scale 1e30 1 1\n", 1,
                   "the composed transform is not finite");
  EXPECT_CSG_ERROR(
      "sphere center 0 0 0 radius 1\nsphere center 0 0 0 radius 1\nunion scale 0 1 1\n", 3,
      "'scale': factors must not be zero");
}

TEST(CsgRpn, MaterialsBelongOnPrimitives) {
  EXPECT_CSG_ERROR(
      "sphere center 0 0 0 radius 1\nsphere center 0 0 0 radius 1\nunion material red\n", 3,
      "'material' belongs on primitives, not on 'union'");
}

// ---------------------------------------------------------------------------------------------
// Files
// ---------------------------------------------------------------------------------------------

// A left-deep chain of unions `levels` deep, as a file that adds primitives one by one makes.
std::string unionChain(int levels) {
  std::string text = "sphere center 0 0 0 radius 1\n";
  for (int i = 1; i < levels; ++i) text += "sphere center 0 0 0 radius 1\nunion\n";
  return text;
}

TEST(CsgRpn, TreesDeeperThanTheLimitAreErrors) {
  // Issue 8: building and intersecting a CSG tree recurse once per level, so a generated file
  // with a 100 000-level chain parsed fine and then overflowed the stack.
  CsgTreeDesc tree = parse(unionChain(kMaxCsgDepth));
  EXPECT_EQ(tree.nodes.size(), size_t(2 * kMaxCsgDepth - 1));
  // Level kMaxCsgDepth + 1 is made by the union on line 2 * kMaxCsgDepth + 1.
  EXPECT_CSG_ERROR(unionChain(kMaxCsgDepth + 1), 2 * kMaxCsgDepth + 1,
                   "'union' makes the tree 1001 levels deep; glint reads CSG trees of at most "
                   "1000 levels");
}

TEST(CsgRpn, LoadsTheDiceExample) {
  std::string path = test::sourceDir() + "/scenes/csg/dice.csg";
  CsgTreeDesc tree = loadCsgRpn(path);
  ASSERT_GE(tree.root, 0);
  const CsgNodeDesc& root = tree.nodes[tree.root];
  EXPECT_EQ(root.op, CsgOp::Difference);
  expectNear(root.parentFromNode.point({0, -1, 0}), {0, 0, 0});  // stands on y = 0
  EXPECT_EQ(root.where.file.rfind(path + ":", 0), 0u);

  // Walk down the left spine: every difference subtracts one pip from the die so far.
  std::set<int> faces;
  int pips = 0, node = tree.root;
  while (tree.nodes[node].op == CsgOp::Difference) {
    const CsgNodeDesc& pip = tree.nodes[tree.nodes[node].children[1]];
    EXPECT_STREQ(pip.shape->typeName(), "sphere");
    EXPECT_EQ(pip.materialName, "ink");
    EXPECT_EQ(pip.material, -1);
    for (int axis = 0; axis < 3; ++axis)
      if (std::abs(test::shapeAs<Sphere>(pip.shape).center()[axis]) == 1)
        faces.insert(axis * 2 + (test::shapeAs<Sphere>(pip.shape).center()[axis] > 0));
    ++pips;
    node = tree.nodes[node].children[0];
  }
  EXPECT_EQ(pips, 1 + 2 + 3 + 4 + 5 + 6);
  EXPECT_EQ(faces.size(), 6u);
  // The rounded cube: a box intersected with a sphere.
  const CsgNodeDesc& body = tree.nodes[node];
  ASSERT_EQ(body.op, CsgOp::Intersection);
  EXPECT_STREQ(tree.nodes[body.children[0]].shape->typeName(), "box");
  EXPECT_STREQ(tree.nodes[body.children[1]].shape->typeName(), "sphere");
  EXPECT_EQ(tree.nodes[body.children[0]].materialName, "ivory");
}

TEST(CsgRpn, LoadErrorsNameTheFileAndLine) {
  std::string path = test::dataDir() + "/csg/leftover.csg";
  SceneError e = errorFrom([&] { loadCsgRpn(path); });
  EXPECT_EQ(e.where().file, path + ":3") << e.what();
  EXPECT_NE(e.message().find("2 nodes remain"), std::string::npos) << e.what();
}

TEST(CsgRpn, LoadingAMissingFileIsAnError) {
  std::string path = test::dataDir() + "/csg/no_such_file.csg";
  SceneError e = errorFrom([&] { loadCsgRpn(path); });
  EXPECT_EQ(std::string(e.what()), path + ": cannot read file");
}

}  // namespace
}  // namespace glint
