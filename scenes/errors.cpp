// glint — SceneError formatting.
#include "scenes/errors.h"

#include <stdexcept>

namespace glint {

namespace {
// RFC 6901: '~' becomes "~0" and '/' becomes "~1" inside a reference token.
std::string escapePointerToken(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~')
      out += "~0";
    else if (c == '/')
      out += "~1";
    else
      out += c;
  }
  return out;
}
}  // namespace

SourceLocation SourceLocation::child(const std::string& key) const {
  return {file, pointer + "/" + escapePointerToken(key)};
}

SourceLocation SourceLocation::child(size_t index) const {
  return {file, pointer + "/" + std::to_string(index)};
}

std::string SourceLocation::str() const {
  if (pointer.empty()) return file;
  return file + ": " + pointer;
}

SceneError::SceneError(SourceLocation where, const std::string& message)
    : InputError(where.str() + ": " + message), where_(std::move(where)), message_(message) {}

std::string quotedNames(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "'" : ", '") + n + "'";
  return list;
}

void namingFile(const std::string& file, const std::string& doing,
                const std::function<void()>& work) {
  try {
    work();
  } catch (const SceneError&) {
    throw;  // names its file and JSON pointer already
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  } catch (const std::logic_error&) {
    throw;  // a bug: main says "internal error"
  } catch (const std::exception& e) {
    throw FailureError(file + ": " + (doing.empty() ? "" : doing + ": ") + e.what());
  }
}

}  // namespace glint
