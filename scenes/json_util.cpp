// glint — JSON reading helpers.
#include "scenes/json_util.h"

#include <fstream>
#include <set>
#include <sstream>
#include <vector>

namespace glint {

namespace {

// The parser callback of parseSceneJson: each open container's location and, for objects, the
// keys seen so far.
class DuplicateKeyCheck {
 public:
  explicit DuplicateKeyCheck(const std::string& file) : file_(file) {}

  bool operator()(int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    switch (event) {
      case Event::object_start:
      case Event::array_start:
        stack_.push_back({event == Event::array_start, 0, elementLocation(), {}, {}});
        break;
      case Event::object_end:
      case Event::array_end:
        stack_.pop_back();
        break;
      case Event::key: {
        Frame& object = stack_.back();
        object.lastKey = parsed.get<std::string>();
        if (!object.keys.insert(object.lastKey).second)
          throw SceneError(object.where, "key '" + object.lastKey + "' given twice");
        break;
      }
      case Event::value:
        if (!stack_.empty() && stack_.back().array) ++stack_.back().count;
        break;
    }
    return true;
  }

 private:
  struct Frame {
    bool array = false;
    size_t count = 0;  // arrays: elements so far
    SourceLocation where;
    std::set<std::string> keys;  // objects
    std::string lastKey;
  };

  // Where the container or value starting now sits (counting it, in an array).
  SourceLocation elementLocation() {
    if (stack_.empty()) return {file_, ""};
    Frame& parent = stack_.back();
    return parent.array ? parent.where.child(parent.count++) : parent.where.child(parent.lastKey);
  }

  std::string file_;
  std::vector<Frame> stack_;
};

nlohmann::json parse(std::string_view text, const std::string& file, bool sceneFile) {
  try {
    if (sceneFile) return nlohmann::json::parse(text.begin(), text.end(), DuplicateKeyCheck(file));
    return nlohmann::json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::parse_error& e) {
    // e.byte is 1-based and points just past the offending character.
    size_t byte = e.byte == 0 ? 0 : e.byte - 1;
    size_t line = 1, column = 1;
    for (size_t i = 0; i < byte && i < text.size(); ++i) {
      if (text[i] == '\n')
        ++line, column = 1;
      else
        ++column;
    }
    // nlohmann's message starts with "[json.exception.parse_error.101] parse error at line..";
    // keep only the part after the last ": " which says what was expected.
    std::string what = e.what();
    size_t colon = what.rfind(": ");
    std::string detail = colon == std::string::npos ? what : what.substr(colon + 2);
    // The message quotes the last token read, which can be a kilobytes-long base64 string.
    if (detail.size() > 120) detail = detail.substr(0, 117) + "...";
    throw SceneError({file + ":" + std::to_string(line) + ":" + std::to_string(column), ""},
                     "JSON syntax error: " + detail);
  } catch (const nlohmann::json::out_of_range& e) {
    // A number too large even for a double ("number overflow parsing '1e400'"): nlohmann gives
    // no position, but its message names the number.
    std::string what = e.what();
    size_t bracket = what.find("] ");
    throw SceneError({file, ""},
                     "JSON number out of range: " +
                         (bracket == std::string::npos ? what : what.substr(bracket + 2)));
  }
}

}  // namespace

nlohmann::json parseJson(std::string_view text, const std::string& file) {
  return parse(text, file, false);
}

nlohmann::json parseSceneJson(std::string_view text, const std::string& file) {
  return parse(text, file, true);
}

std::string readTextFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError({path, ""}, "cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw SceneError({path, ""}, "cannot read file");
  return ss.str();
}

std::string jsonTypeName(const nlohmann::json& value) {
  switch (value.type()) {
    case nlohmann::json::value_t::null:
      return "null";
    case nlohmann::json::value_t::object:
      return "object";
    case nlohmann::json::value_t::array:
      return "array";
    case nlohmann::json::value_t::string:
      return "string";
    case nlohmann::json::value_t::boolean:
      return "boolean";
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned:
      return "integer";
    case nlohmann::json::value_t::number_float:
      return "number";
    default:
      return "value";
  }
}

}  // namespace glint
