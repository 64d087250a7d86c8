// glint — the reverse-polish .csg format: a stack machine over token-lines (see csg_rpn.h).
#include "scenes/csg_rpn.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "geometry/shapes/registry.h"
#include "scenes/json_reader.h"  // closestMatch

namespace glint {

namespace {

// ---------------------------------------------------------------------------------------------
// Vocabulary
// ---------------------------------------------------------------------------------------------

struct KeySpec {
  std::string name;
  int count;  // numbers after the key
};

// A registered shape the format can name (geometry/shapes/registry.h): the solids.
struct PrimitiveSpec {
  std::string name;
  const ShapeKind* kind;
  std::vector<KeySpec> keys;  // all required
};

const std::vector<PrimitiveSpec>& primitives() {
  static const std::vector<PrimitiveSpec> specs = [] {
    std::vector<PrimitiveSpec> out;
    for (const ShapeKind& kind : shapeKinds()) {
      if (kind.csgKeys.empty()) continue;  // never a solid, so never a leaf
      PrimitiveSpec spec{kind.name, &kind, {}};
      for (const ShapeKey& key : kind.csgKeys) spec.keys.push_back({key.name, key.count});
      out.push_back(std::move(spec));
    }
    return out;
  }();
  return specs;
}

const std::map<std::string, CsgOp> kOperators = {{"union", CsgOp::Union},
                                                 {"intersection", CsgOp::Intersection},
                                                 {"difference", CsgOp::Difference}};

const std::vector<KeySpec> kTransformOps = {
    {"translate", 3}, {"rotate", 4}, {"scale", 3}, {"shear", 6}};

const std::string kMaterial = "material";

const PrimitiveSpec* findPrimitive(const std::string& word) {
  for (const PrimitiveSpec& p : primitives())
    if (p.name == word) return &p;
  return nullptr;
}

const KeySpec* findKey(const std::vector<KeySpec>& keys, const std::string& word) {
  for (const KeySpec& k : keys)
    if (k.name == word) return &k;
  return nullptr;
}

// Every word the format knows: a number cut short by one of these is "too few numbers".
bool isKeyword(const std::string& word) {
  if (findPrimitive(word) || kOperators.count(word) || findKey(kTransformOps, word) ||
      word == kMaterial)
    return true;
  for (const PrimitiveSpec& p : primitives())
    if (findKey(p.keys, word)) return true;
  return false;
}

std::string inQuotes(const std::string& word) { return "'" + word + "'"; }

std::string withSuggestion(std::string message, const std::string& word,
                           const std::vector<std::string>& candidates) {
  std::string guess = closestMatch(word, candidates);
  if (!guess.empty()) return message + "; did you mean " + inQuotes(guess) + "?";
  message += "; expected one of ";
  for (size_t i = 0; i < candidates.size(); ++i)
    message += (i ? ", " : "") + inQuotes(candidates[i]);
  return message;
}

std::string numbers(int count) {
  return std::to_string(count) + (count == 1 ? " number" : " numbers");
}

// A decimal number (an optional leading '+' is allowed); nullopt when the word is not one.
std::optional<double> parseNumber(const std::string& word) {
  const char* first = word.data();
  const char* last = first + word.size();
  if (first != last && *first == '+') ++first;
  double value = 0;
  auto [end, error] = std::from_chars(first, last, value);
  // Out of double range is still a number: strtod tells overflow (inf) from underflow (~0).
  if (error == std::errc::result_out_of_range && end == last) return std::strtod(first, nullptr);
  if (error != std::errc() || end != last || first == last) return std::nullopt;
  return value;
}

// ---------------------------------------------------------------------------------------------
// One token-line: its words, read left to right
// ---------------------------------------------------------------------------------------------

class TokenLine {
 public:
  TokenLine(std::vector<std::string> words, int line, const std::string& file)
      : words_(std::move(words)), line_(line), where_{file + ":" + std::to_string(line), ""} {}

  const std::string& head() const { return words_[0]; }
  int line() const { return line_; }
  const SourceLocation& where() const { return where_; }
  [[noreturn]] void fail(const std::string& message) const { throw SceneError(where_, message); }

  bool done() const { return next_ >= words_.size(); }
  const std::string& next() { return words_[next_++]; }

  // The `count` numbers after `key` (just read).
  std::vector<float> numbersFor(const std::string& key, int count) {
    std::vector<float> values;
    while (int(values.size()) < count) {
      if (done() || isKeyword(words_[next_]))
        fail(inQuotes(key) + " needs " + numbers(count) + ", got " + std::to_string(values.size()));
      const std::string& word = next();
      std::optional<double> v = parseNumber(word);
      if (!v) fail("expected a number after " + inQuotes(key) + ", got " + inQuotes(word));
      if (!std::isfinite(*v) || std::abs(*v) > std::numeric_limits<float>::max())
        fail(inQuotes(key) + ": " + inQuotes(word) + " is not a finite number");
      values.push_back(float(*v));
    }
    return values;
  }

  // A word where a key was expected.
  [[noreturn]] void unknownKey(const std::string& word, const std::string& lastKey,
                               const std::vector<std::string>& candidates) const {
    // A stray number most likely means one too many for the key before it.
    if (parseNumber(word))
      fail("unexpected number " + inQuotes(word) + " after " +
           inQuotes(lastKey.empty() ? head() : lastKey));
    fail(withSuggestion("unknown key " + inQuotes(word) + " for " + inQuotes(head()), word,
                        candidates));
  }

 private:
  std::vector<std::string> words_;
  size_t next_ = 1;  // words_[0] is the token
  int line_;
  SourceLocation where_;
};

// The words of each non-empty line, comments stripped.
std::vector<TokenLine> splitLines(const std::string& text, const std::string& file,
                                  int* lineCount) {
  std::vector<TokenLine> lines;
  std::istringstream in(text);
  std::string raw;
  int number = 0;
  while (std::getline(in, raw)) {
    ++number;
    if (size_t hash = raw.find('#'); hash != std::string::npos) raw.resize(hash);
    std::vector<std::string> words;
    std::istringstream wordsIn(raw);  // splits on spaces, tabs and a trailing '\r'
    for (std::string w; wordsIn >> w;) words.push_back(w);
    if (!words.empty()) lines.emplace_back(std::move(words), number, file);
  }
  *lineCount = number;
  return lines;
}

// ---------------------------------------------------------------------------------------------
// Transforms
// ---------------------------------------------------------------------------------------------

Transform transformOperation(const TokenLine& line, const std::string& op,
                             const std::vector<float>& v) {
  if (op == "translate") return Transform::translate({v[0], v[1], v[2]});
  if (op == "rotate") {
    Vec3f axis{v[1], v[2], v[3]};
    if (axis == Vec3f{}) line.fail("'rotate': the rotation axis must not be zero");
    return Transform::rotate(v[0], axis);
  }
  if (op == "scale") {
    if (v[0] == 0 || v[1] == 0 || v[2] == 0) line.fail("'scale': factors must not be zero");
    return Transform::scale({v[0], v[1], v[2]});
  }
  // shear XY XZ YX YZ ZX ZY: the off-diagonal entries of the 3x3 part.
  Mat4 m;
  m.m[0][1] = v[0], m.m[0][2] = v[1];
  m.m[1][0] = v[2], m.m[1][2] = v[3];
  m.m[2][0] = v[4], m.m[2][1] = v[5];
  Mat4 inverse;
  if (!invert(m, &inverse)) line.fail("'shear': the shear matrix is singular");
  return Transform(m, inverse);
}

// Applies one operation after the node's transform so far, as meant too.
void applyOperation(const TokenLine& line, const std::string& op, const std::vector<float>& v,
                    CsgNodeDesc* node) {
  const Transform t = transformOperation(line, op, v);
  const MeantTransform meant = op == "rotate" ? MeantTransform::rotation(v[0], {v[1], v[2], v[3]})
                                              : MeantTransform::written(t.matrix());
  node->parentFromNodeMeant = meant * node->parentFromNodeMeant;
  node->parentFromNode = t * node->parentFromNode;
}

// Checks the node's composed transform once all its operations are read.
void checkTransform(const TokenLine& line, const Transform& t) {
  for (const auto& row : t.matrix().m)
    for (float x : row)
      if (!std::isfinite(x)) line.fail("the composed transform is not finite");
  Mat4 inverse;
  if (!invert(t.matrix(), &inverse)) line.fail("the composed transform is singular");
}

// ---------------------------------------------------------------------------------------------
// Token-lines to nodes
// ---------------------------------------------------------------------------------------------

Vec3f vec3(const std::vector<float>& v) { return {v[0], v[1], v[2]}; }

// A primitive's parameters from the numbers its line gave each key (all of the shape's
// .csg keys are present; any other key takes the shape's default, e.g. cylinders are capped).
// Errors at file:line.
class CsgShapeParameters final : public ShapeParameters {
 public:
  CsgShapeParameters(const TokenLine& line, const std::string& shape,
                     const std::map<std::string, std::vector<float>>& values)
      : line_(line), shape_(shape), values_(values) {}

  float positive(const char* key, std::optional<float> fallback) override {
    const std::vector<float>* v = find(key);
    if (!v) return defaultOf(key, fallback);
    if (!((*v)[0] > 0)) {
      std::ostringstream out;
      out << inQuotes(key) << " must be > 0, got " << (*v)[0];
      line_.fail(out.str());
    }
    return (*v)[0];
  }
  Vec3f vector(const char* key, std::optional<Vec3f> fallback) override {
    const std::vector<float>* v = find(key);
    return v ? vec3(*v) : defaultOf(key, fallback);
  }
  bool flag(const char*, bool fallback) override { return fallback; }
  [[noreturn]] void invalid(const char* key, const std::string& message) override {
    line_.fail(shape_ + " " + inQuotes(key) + " " + message);
  }

 private:
  // The key's numbers; nullptr for a key the format does not write (the default applies; a
  // required key missing from the shape's .csg keys is a mistake in the registry).
  const std::vector<float>* find(const char* key) const {
    auto it = values_.find(key);
    return it == values_.end() ? nullptr : &it->second;
  }

  template <class T>
  static T defaultOf(const char* key, std::optional<T> fallback) {
    if (!fallback)
      throw std::logic_error(std::string("shape registry: required key '") + key +
                             "' is missing from the shape's .csg keys");
    return *fallback;
  }

  const TokenLine& line_;
  const std::string& shape_;
  const std::map<std::string, std::vector<float>>& values_;
};

CsgNodeDesc parsePrimitive(TokenLine& line, const PrimitiveSpec& spec) {
  CsgNodeDesc node;
  node.where = line.where();
  std::vector<std::string> candidates;
  for (const KeySpec& k : spec.keys) candidates.push_back(k.name);
  candidates.push_back(kMaterial);
  for (const KeySpec& k : kTransformOps) candidates.push_back(k.name);

  std::map<std::string, std::vector<float>> values;
  bool hasMaterial = false;
  std::string lastKey;
  while (!line.done()) {
    const std::string& word = line.next();
    if (const KeySpec* key = findKey(spec.keys, word)) {
      if (values.count(word)) line.fail(inQuotes(word) + " given twice");
      values[word] = line.numbersFor(word, key->count);
    } else if (const KeySpec* op = findKey(kTransformOps, word)) {
      applyOperation(line, word, line.numbersFor(word, op->count), &node);
    } else if (word == kMaterial) {
      if (hasMaterial) line.fail("'material' given twice");
      if (line.done()) line.fail("'material' needs a name");
      node.materialName = line.next();
      hasMaterial = true;
    } else {
      line.unknownKey(word, lastKey, candidates);
    }
    lastKey = word;
  }
  for (const KeySpec& k : spec.keys)
    if (!values.count(k.name))
      line.fail(inQuotes(spec.name) + " needs " + inQuotes(k.name) + " (" + numbers(k.count) + ")");
  checkTransform(line, node.parentFromNode);

  CsgShapeParameters params(line, spec.name, values);
  node.shape = spec.kind->create(params);
  if (!node.shape->isSolid()) line.fail(inQuotes(spec.name) + " is not a closed solid here");
  return node;
}

CsgNodeDesc parseOperator(TokenLine& line, CsgOp op) {
  CsgNodeDesc node;
  node.op = op;
  node.where = line.where();
  std::vector<std::string> candidates;
  for (const KeySpec& k : kTransformOps) candidates.push_back(k.name);
  std::string lastKey;
  while (!line.done()) {
    const std::string& word = line.next();
    if (const KeySpec* t = findKey(kTransformOps, word)) {
      applyOperation(line, word, line.numbersFor(word, t->count), &node);
    } else if (word == kMaterial) {
      line.fail("'material' belongs on primitives, not on " + inQuotes(line.head()));
    } else {
      line.unknownKey(word, lastKey, candidates);
    }
    lastKey = word;
  }
  checkTransform(line, node.parentFromNode);
  return node;
}

std::vector<std::string> tokenNames() {
  std::vector<std::string> names;
  for (const PrimitiveSpec& p : primitives()) names.push_back(p.name);
  for (const auto& [name, op] : kOperators) names.push_back(name);
  return names;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Entry points
// ---------------------------------------------------------------------------------------------

CsgTreeDesc parseCsgRpn(const std::string& text, const std::string& file) {
  int lineCount = 0;
  std::vector<TokenLine> lines = splitLines(text, file, &lineCount);
  CsgTreeDesc tree;
  std::vector<int> stack;      // node indices
  std::vector<int> nodeLines;  // the line of each node
  std::vector<int> depths;     // the levels of each node's subtree
  for (TokenLine& line : lines) {
    const std::string& token = line.head();
    if (const PrimitiveSpec* spec = findPrimitive(token)) {
      tree.nodes.push_back(parsePrimitive(line, *spec));
      depths.push_back(1);
    } else if (auto op = kOperators.find(token); op != kOperators.end()) {
      // Report underflow before the transforms: the missing operand is the bigger mistake.
      if (stack.size() < 2)
        line.fail("stack underflow: " + inQuotes(token) + " needs 2 operands, the stack holds " +
                  std::to_string(stack.size()));
      CsgNodeDesc node = parseOperator(line, op->second);
      int right = stack.back();
      stack.pop_back();
      int left = stack.back();
      stack.pop_back();
      int depth = 1 + std::max(depths[size_t(left)], depths[size_t(right)]);
      if (depth > kMaxCsgDepth)
        line.fail(inQuotes(token) + " makes the tree " + std::to_string(depth) +
                  " levels deep; glint reads CSG trees of at most " + std::to_string(kMaxCsgDepth) +
                  " levels");
      node.children = {left, right};
      tree.nodes.push_back(std::move(node));
      depths.push_back(depth);
    } else {
      line.fail(withSuggestion("unknown token " + inQuotes(token), token, tokenNames()));
    }
    stack.push_back(int(tree.nodes.size()) - 1);
    nodeLines.push_back(line.line());
  }

  if (stack.empty()) {
    SourceLocation end{file + ":" + std::to_string(std::max(lineCount, 1)), ""};
    throw SceneError(end, "empty CSG file: no primitive or operator");
  }
  if (stack.size() > 1) {
    // Point at the bottom of the stack: the oldest node nothing combined.
    int first = stack.front();
    throw SceneError(tree.nodes[first].where,
                     "leftover operands: " + std::to_string(stack.size()) +
                         " nodes remain on the stack at the end of the file, expected 1; the "
                         "first unconsumed one is on line " +
                         std::to_string(nodeLines[first]) + " (combine them with an operator)");
  }
  tree.root = stack.back();
  return tree;
}

CsgTreeDesc loadCsgRpn(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  if (in) text << in.rdbuf();
  if (!in || in.bad()) throw SceneError({path, ""}, "cannot read file");
  return parseCsgRpn(text.str(), path);
}

}  // namespace glint
