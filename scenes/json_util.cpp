// glint — JSON reading helpers.
#include "scenes/json_util.h"

#include <fstream>
#include <sstream>

namespace glint {

nlohmann::json parseJson(std::string_view text, const std::string& file) {
  try {
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
    throw SceneError({file, ""}, "JSON number out of range: " +
                                     (bracket == std::string::npos ? what : what.substr(bracket + 2)));
  }
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
    case nlohmann::json::value_t::null: return "null";
    case nlohmann::json::value_t::object: return "object";
    case nlohmann::json::value_t::array: return "array";
    case nlohmann::json::value_t::string: return "string";
    case nlohmann::json::value_t::boolean: return "boolean";
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned: return "integer";
    case nlohmann::json::value_t::number_float: return "number";
    default: return "value";
  }
}

}  // namespace glint
