// glint — JsonReader: typed, located reading of JSON objects.
#include "scenes/json_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>

#include "scenes/json_util.h"

namespace glint {

using Json = nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Messages
// ---------------------------------------------------------------------------------------------

namespace {

std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string quotedList(const std::vector<std::string>& names) {
  std::string out;
  for (size_t i = 0; i < names.size(); ++i) out += (i ? ", '" : "'") + names[i] + "'";
  return out;
}

// Optimal string alignment distance (Levenshtein plus adjacent transpositions), ignoring case.
size_t editDistance(std::string_view a, std::string_view b) {
  auto lower = [](char c) { return char(std::tolower(static_cast<unsigned char>(c))); };
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i)
    for (size_t j = 1; j <= b.size(); ++j) {
      size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) &&
          lower(a[i - 2]) == lower(b[j - 1]))
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

// "number" (strict) or "a number" (lenient): the type a value should have had, as each mode
// words it (JsonMode).
std::string typeName(const std::string& noun, JsonMode mode) {
  if (mode == JsonMode::Strict) return noun;
  return (std::string_view("aeiou").find(noun[0]) != std::string_view::npos ? "an " : "a ") + noun;
}

[[noreturn]] void wrongType(const Json& value, const SourceLocation& where,
                            const std::string& expected, JsonMode mode = JsonMode::Strict) {
  throw SceneError(where, "expected " + typeName(expected, mode) + ", got " + jsonTypeName(value));
}

}  // namespace

std::string Range::describe() const {
  std::vector<std::string> parts;
  if (gt) parts.push_back("> " + formatNumber(*gt));
  if (ge) parts.push_back(">= " + formatNumber(*ge));
  if (lt) parts.push_back("< " + formatNumber(*lt));
  if (le) parts.push_back("<= " + formatNumber(*le));
  std::string out = "must be";
  for (size_t i = 0; i < parts.size(); ++i) out += (i ? " and " : " ") + parts[i];
  return out;
}

std::string closestMatch(std::string_view word, const std::vector<std::string>& candidates) {
  // Allow about one edit per three characters: "spq" -> "spp", "radus" -> "radius".
  size_t allowed = std::clamp<size_t>(word.size() / 3, 1, 3);
  std::string best;
  size_t bestDistance = allowed + 1;
  for (const std::string& c : candidates) {
    size_t d = editDistance(word, c);
    if (d < bestDistance && d < std::max(word.size(), c.size())) best = c, bestDistance = d;
  }
  return best;
}

// ---------------------------------------------------------------------------------------------
// Value conversion
// ---------------------------------------------------------------------------------------------

namespace {

void checkRange(double v, const SourceLocation& where, const Range& range) {
  if (!range.contains(v)) throw SceneError(where, range.describe());
}

// A number finite as a float, as written (not yet rounded).
double toFiniteNumber(const Json& value, const SourceLocation& where, JsonMode mode) {
  if (!value.is_number()) wrongType(value, where, "number", mode);
  double d = value.get<double>();
  // JSON has no NaN or Inf, but 1e39 overflows a float (and 1e400 a double).
  if (!std::isfinite(d) || std::abs(d) > double(std::numeric_limits<float>::max()))
    throw SceneError(where, "must be finite (the number is too large for a float)");
  return d;
}

float toFloat(const Json& value, const SourceLocation& where, const Range& range,
              JsonMode mode = JsonMode::Strict) {
  float f = float(toFiniteNumber(value, where, mode));
  checkRange(double(f), where, range);
  return f;
}

// Checks that `value` is an array of `n` elements, worded as `mode` words it.
void checkArrayOf(const Json& value, const SourceLocation& where, size_t n, JsonMode mode) {
  std::string expected = "an array of " + std::to_string(n) + " numbers";
  if (mode == JsonMode::Lenient) {
    if (!value.is_array() || value.size() != n) throw SceneError(where, "expected " + expected);
    return;
  }
  if (!value.is_array()) wrongType(value, where, expected);
  if (value.size() != n)
    throw SceneError(
        where, "expected " + std::to_string(n) + " numbers, got " + std::to_string(value.size()));
}

template <size_t N>
std::array<float, N> toFloats(const Json& value, const SourceLocation& where, const Range& range,
                              JsonMode mode = JsonMode::Strict) {
  checkArrayOf(value, where, N, mode);
  std::array<float, N> out;
  for (size_t i = 0; i < N; ++i) out[i] = toFloat(value[i], where.child(i), range, mode);
  return out;
}

// A value as an error message shows it: "number -1.5", "string \"three\"", "object".
std::string describeValue(const Json& v) {
  if (v.is_number()) return "number " + v.dump();
  if (v.is_string()) return "string " + v.dump();
  return jsonTypeName(v);
}

// "3 accessors", "1 mesh", "2 meshes".
std::string countOf(size_t n, std::string_view what) {
  std::string out = std::to_string(n) + " " + std::string(what);
  if (n == 1) return out;
  const bool sibilant =
      what.ends_with("s") || what.ends_with("sh") || what.ends_with("ch") || what.ends_with("x");
  return out + (sibilant ? "es" : "s");
}

Vec3f toVec3(const Json& value, const SourceLocation& where) {
  auto v = toFloats<3>(value, where, {});
  return {v[0], v[1], v[2]};
}

// The 4x4 matrix forms: 16 numbers row-major, or 4 rows of 4. Checked to be finite, affine
// and invertible.
Transform toMatrix(const Json& value, const SourceLocation& where) {
  Mat4 m;
  if (value.is_array() && value.size() == 16) {
    for (size_t i = 0; i < 16; ++i) m.m[i / 4][i % 4] = toFloat(value[i], where.child(i), {});
  } else if (value.is_array() && value.size() == 4 &&
             std::all_of(value.begin(), value.end(), [](const Json& r) { return r.is_array(); })) {
    for (size_t r = 0; r < 4; ++r) {
      auto row = toFloats<4>(value[r], where.child(r), {});
      for (size_t c = 0; c < 4; ++c) m.m[r][c] = row[c];
    }
  } else if (value.is_array()) {
    throw SceneError(where, "expected a 4x4 matrix: 16 numbers (row-major) or 4 rows of 4, got " +
                                std::to_string(value.size()) + " elements");
  } else {
    wrongType(value, where, "a 4x4 matrix");
  }
  if (m.m[3][0] != 0 || m.m[3][1] != 0 || m.m[3][2] != 0 || m.m[3][3] != 1)
    throw SceneError(where, "the last row of a matrix must be [0, 0, 0, 1] (affine)");
  Mat4 inverse;
  if (!invert(m, &inverse)) throw SceneError(where, "matrix is singular (not invertible)");
  return Transform(m, inverse);
}

const std::vector<std::string> kTransformOps = {"translate", "rotate", "scale", "shear", "matrix"};

// One operation; `meant` receives it as meant.
Transform toOperation(const Json& op, const SourceLocation& where, MeantTransform* meant) {
  if (!op.is_object()) wrongType(op, where, "a transform operation object");
  if (op.size() != 1)
    throw SceneError(where, "a transform operation has exactly one key (one of " +
                                quotedList(kTransformOps) + "), got " + std::to_string(op.size()));
  const std::string& name = op.begin().key();
  const Json& arg = op.begin().value();
  SourceLocation at = where.child(name);
  if (name == "translate") {
    Transform t = Transform::translate(toVec3(arg, at));
    *meant = MeantTransform::written(t.matrix());
    return t;
  }
  if (name == "scale") {
    Vec3f s = arg.is_number() ? Vec3f{1, 1, 1} * toFloat(arg, at, {}) : toVec3(arg, at);
    if (s.x == 0 || s.y == 0 || s.z == 0) throw SceneError(at, "scale must not be zero");
    Transform t = Transform::scale(s);
    *meant = MeantTransform::written(t.matrix());
    return t;
  }
  if (name == "rotate") {
    JsonReader r(arg, at);
    Vec3f axis = toVec3(r.require("axis"), r.where("axis"));
    float degrees = r.get<float>("degrees");
    r.finish();
    if (axis == Vec3f{}) throw SceneError(r.where("axis"), "rotation axis must not be zero");
    *meant = MeantTransform::rotation(degrees, axis);
    return Transform::rotate(degrees, axis);
  }
  if (name == "shear") {
    // {"xy": a, ...}: x' = x + xy * y + xz * z, y' = yx * x + y + yz * z, z' = ... (unset = 0)
    JsonReader r(arg, at);
    Mat4 m;
    const char* keys[3][3] = {{nullptr, "xy", "xz"}, {"yx", nullptr, "yz"}, {"zx", "zy", nullptr}};
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 3; ++col)
        if (keys[row][col]) m.m[row][col] = r.get<float>(keys[row][col], 0.0f);
    r.finish();
    Mat4 inverse;
    if (!invert(m, &inverse)) throw SceneError(at, "shear is singular (not invertible)");
    *meant = MeantTransform::written(m);
    return Transform(m, inverse);
  }
  if (name == "matrix") {
    Transform t = toMatrix(arg, at);
    *meant = MeantTransform::written(t.matrix());
    return t;
  }
  std::string message = "unknown transform operation '" + name + "'";
  if (std::string guess = closestMatch(name, kTransformOps); !guess.empty())
    message += "; did you mean '" + guess + "'?";
  else
    message += "; expected one of " + quotedList(kTransformOps);
  throw SceneError(at, message);
}

}  // namespace

size_t readSize(const Json& value, const SourceLocation& where) {
  if (value.is_number_unsigned()) return value.get<size_t>();
  if (value.is_number_integer())
    throw SceneError(where,
                     "must not be negative (got " + std::to_string(value.get<int64_t>()) + ")");
  if (value.is_number_float()) {
    double d = value.get<double>();
    if (d >= 0 && d == std::floor(d) && d < 9e15) return size_t(d);
  }
  throw SceneError(where, "expected a non-negative integer, got " + describeValue(value));
}

int readIndex(const Json& value, const SourceLocation& where, size_t count, std::string_view what) {
  size_t i = readSize(value, where);
  if (i >= count)
    throw SceneError(where, std::string(what) + " " + std::to_string(i) + " does not exist (" +
                                countOf(count, what) + " in the file)");
  return int(i);
}

void readNumbers(const Json& value, const SourceLocation& where, double* out, size_t n,
                 const Range& range, JsonMode mode) {
  checkArrayOf(value, where, n, mode);
  for (size_t i = 0; i < n; ++i) out[i] = readValue<double>(value[i], where.child(i), range, mode);
}

Transform readTransform(const Json& value, const SourceLocation& where, MeantTransform* meant) {
  if (!value.is_array()) wrongType(value, where, "a 4x4 matrix or a list of transform operations");
  MeantTransform composed;
  if (!meant) meant = &composed;
  *meant = {};
  bool opList =
      std::all_of(value.begin(), value.end(), [](const Json& v) { return v.is_object(); });
  if (!opList || value.empty()) {
    if (value.empty()) return Transform();
    Transform t = toMatrix(value, where);
    *meant = MeantTransform::written(t.matrix());
    return t;
  }
  // Applied in order: the first operation is applied to the object first.
  Transform t;
  for (size_t i = 0; i < value.size(); ++i) {
    MeantTransform opMeant;
    Transform op = toOperation(value[i], where.child(i), &opMeant);
    *meant = opMeant * *meant;
    t = op * t;
  }
  const Mat4& m = t.matrix();
  Mat4 check;
  for (const auto& row : m.m)
    for (float x : row)
      if (!std::isfinite(x)) throw SceneError(where, "the composed transform is not finite");
  if (!invert(m, &check)) throw SceneError(where, "the composed transform is singular");
  return t;
}

template <>
bool readValue<bool>(const Json& value, const SourceLocation& where, const Range&, JsonMode mode) {
  if (!value.is_boolean()) wrongType(value, where, "boolean", mode);
  return value.get<bool>();
}

template <>
int readValue<int>(const Json& value, const SourceLocation& where, const Range& range,
                   JsonMode mode) {
  if (!value.is_number_integer()) wrongType(value, where, "integer", mode);
  bool fits = value.is_number_unsigned()
                  ? value.get<uint64_t>() <= uint64_t(std::numeric_limits<int>::max())
                  : value.get<int64_t>() >= std::numeric_limits<int>::min() &&
                        value.get<int64_t>() <= std::numeric_limits<int>::max();
  if (!fits) throw SceneError(where, "integer out of range");
  int v = value.get<int>();
  checkRange(double(v), where, range);
  return v;
}

template <>
uint64_t readValue<uint64_t>(const Json& value, const SourceLocation& where, const Range& range,
                             JsonMode mode) {
  if (!value.is_number_integer()) wrongType(value, where, "integer", mode);
  if (!value.is_number_unsigned() && value.get<int64_t>() < 0)
    throw SceneError(where, "must be >= 0");
  uint64_t v = value.get<uint64_t>();
  checkRange(double(v), where, range);
  return v;
}

template <>
float readValue<float>(const Json& value, const SourceLocation& where, const Range& range,
                       JsonMode mode) {
  return toFloat(value, where, range, mode);
}

template <>
double readValue<double>(const Json& value, const SourceLocation& where, const Range& range,
                         JsonMode mode) {
  double d;
  if (mode == JsonMode::Lenient) {
    // glint keeps every glTF number as a float: it must fit one. It is returned unrounded, so
    // that bounds are checked on the number as written.
    d = toFiniteNumber(value, where, mode);
  } else {
    // The sidecar's doubles (the scene time, fps) are doubles: finite is enough.
    if (!value.is_number()) wrongType(value, where, "number", mode);
    d = value.get<double>();
    if (!std::isfinite(d)) throw SceneError(where, "must be finite");
  }
  checkRange(d, where, range);
  return d;
}

template <>
std::string readValue<std::string>(const Json& value, const SourceLocation& where, const Range&,
                                   JsonMode mode) {
  if (!value.is_string()) wrongType(value, where, "string", mode);
  return value.get<std::string>();
}

template <>
Vec2f readValue<Vec2f>(const Json& value, const SourceLocation& where, const Range& range,
                       JsonMode mode) {
  auto v = toFloats<2>(value, where, range, mode);
  return {v[0], v[1]};
}

template <>
Vec3f readValue<Vec3f>(const Json& value, const SourceLocation& where, const Range& range,
                       JsonMode mode) {
  auto v = toFloats<3>(value, where, range, mode);
  return {v[0], v[1], v[2]};
}

template <>
Quaternion readValue<Quaternion>(const Json& value, const SourceLocation& where, const Range&,
                                 JsonMode mode) {
  auto q = toFloats<4>(value, where, {}, mode);
  Quaternion r{q[0], q[1], q[2], q[3]};
  if (!(dot(r, r) > 1e-12f)) throw SceneError(where, "quaternion must not be zero");
  return normalize(r);
}

template <>
Transform readValue<Transform>(const Json& value, const SourceLocation& where, const Range&,
                               JsonMode) {
  return readTransform(value, where);
}

bool isKeyframes(const Json& value) { return value.is_object() && value.contains("keys"); }

// ---------------------------------------------------------------------------------------------
// JsonReader
// ---------------------------------------------------------------------------------------------

JsonReader::JsonReader(const Json& object, SourceLocation where, std::optional<double> time)
    : JsonReader(object, std::move(where), time, JsonMode::Strict) {}

JsonReader::JsonReader(const Json& object, SourceLocation where, JsonMode mode)
    : JsonReader(object, std::move(where), std::nullopt, mode) {}

JsonReader::JsonReader(const JsonItem& element)
    : JsonReader(*element.value, element.where, std::nullopt, element.mode) {}

JsonReader::JsonReader(const Json& object, SourceLocation where, std::optional<double> time,
                       JsonMode mode)
    : object_(&object), where_(std::move(where)), time_(time), mode_(mode) {
  if (!object.is_object()) wrongType(object, where_, "object", mode_);
}

JsonReader& JsonReader::child(const Json& value, SourceLocation at) {
  children_.push_back(
      std::unique_ptr<JsonReader>(new JsonReader(value, std::move(at), time_, mode_)));
  return *children_.back();
}

bool JsonReader::has(std::string_view key) const { return object_->contains(key); }

// Lenient readers keep no record: their finish() accepts every key.
void JsonReader::markKnown(std::string_view key) {
  if (mode_ == JsonMode::Strict && known_.find(key) == known_.end()) known_.emplace(key);
}

const Json* JsonReader::take(std::string_view key) {
  markKnown(key);
  auto it = object_->find(key);
  if (it == object_->end()) return nullptr;
  if (mode_ == JsonMode::Strict && read_.find(key) == read_.end()) read_.emplace(key);
  return &*it;
}

const Json& JsonReader::require(std::string_view key) {
  const Json* v = take(key);
  if (!v)
    throw SceneError(where_, std::string("missing required ") +
                                 (mode_ == JsonMode::Strict ? "key" : "property") + " '" +
                                 std::string(key) + "'");
  return *v;
}

size_t JsonReader::getSize(std::string_view key) { return readSize(require(key), where(key)); }

size_t JsonReader::getSize(std::string_view key, size_t fallback) {
  const Json* v = take(key);
  return v ? readSize(*v, where(key)) : fallback;
}

int JsonReader::index(std::string_view key, size_t count, std::string_view what) {
  return readIndex(require(key), where(key), count, what);
}

int JsonReader::index(std::string_view key, size_t count, std::string_view what, int fallback) {
  const Json* v = take(key);
  return v ? readIndex(*v, where(key), count, what) : fallback;
}

std::string JsonReader::oneOf(std::string_view key, const std::vector<std::string>& allowed) {
  std::string value = get<std::string>(key);
  if (std::find(allowed.begin(), allowed.end(), value) != allowed.end()) return value;
  std::string message = "'" + value + "' is not one of " + quotedList(allowed);
  if (std::string guess = closestMatch(value, allowed); !guess.empty())
    message += "; did you mean '" + guess + "'?";
  throw SceneError(where(key), message);
}

std::string JsonReader::oneOf(std::string_view key, const std::vector<std::string>& allowed,
                              const std::string& fallback) {
  if (!has(key)) {
    markKnown(key);
    return fallback;
  }
  return oneOf(key, allowed);
}

JsonReader& JsonReader::object(std::string_view key) {
  const Json& v = require(key);
  return child(v, where(key));
}

JsonReader* JsonReader::optionalObject(std::string_view key) {
  if (!has(key)) {
    markKnown(key);
    return nullptr;
  }
  return &object(key);
}

std::vector<JsonItem> JsonReader::array(std::string_view key) {
  const Json& v = require(key);
  SourceLocation at = where(key);
  if (!v.is_array()) wrongType(v, at, "array", mode_);
  std::vector<JsonItem> items;
  items.reserve(v.size());
  for (size_t i = 0; i < v.size(); ++i) items.push_back({&v[i], at.child(i), mode_});
  return items;
}

std::vector<JsonItem> JsonReader::optionalArray(std::string_view key) {
  if (!has(key)) {
    markKnown(key);
    return {};
  }
  return array(key);
}

JsonReader& JsonReader::item(const JsonItem& element) {
  return child(*element.value, element.where);
}

std::vector<JsonReader*> JsonReader::objects(std::string_view key) {
  std::vector<JsonReader*> readers;
  for (const JsonItem& element : optionalArray(key)) readers.push_back(&item(element));
  return readers;
}

void JsonReader::finish() const {
  if (mode_ == JsonMode::Lenient) return;  // and so are its children
  for (const auto& [key, value] : object_->items()) {
    if (read_.find(key) != read_.end()) continue;
    std::string message = "unknown key '" + key + "'";
    std::vector<std::string> known(known_.begin(), known_.end());
    if (std::string guess = closestMatch(key, known); !guess.empty())
      message += "; did you mean '" + guess + "'?";
    throw SceneError(where_.child(key), message);
  }
  for (const auto& child : children_) child->finish();
}

}  // namespace glint
