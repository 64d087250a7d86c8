// glint — errors in user input, carried with their source location until main prints them.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "geometry/error.h"

namespace glint {

// Where a value came from: a file and a JSON pointer into it ("/meshes/0/primitives/1").
// For files that are not JSON (or errors about the whole file) the pointer is empty.
struct SourceLocation {
  std::string file;
  std::string pointer;

  SourceLocation child(const std::string& key) const;  // pointer + "/" + escaped key
  SourceLocation child(size_t index) const;
  std::string str() const;  // "file: /pointer" or "file"
};

// A problem with the user's input. what() is the one-line message main prints:
// "scene.json: /objects/3/radius: must be > 0". Loaders throw it; main catches it once (as an
// InputError, geometry/error.h) and exits with code 2. Never thrown through an Embree callback.
class SceneError : public InputError {
 public:
  SceneError(SourceLocation where, const std::string& message);
  const SourceLocation& where() const { return where_; }
  const std::string& message() const { return message_; }

 private:
  SourceLocation where_;
  std::string message_;
};

// "'a', 'b', 'c'": the names an error message offers as the choices there were.
std::string quotedNames(const std::vector<std::string>& names);

// Runs `work`, which loads, builds or renders `file`, so that its errors name the file: a bad
// input that does not name it already (a renderer setting, a tile count above the image height)
// becomes the InputError "FILE: message"; a std::logic_error (a bug) passes as it is; anything
// else that is not a SceneError becomes the failure "FILE: DOING: message" (or "FILE: message"
// without `doing`: a failed write, out of memory, an Embree failure). The renderer cannot say
// which file its settings came from; this is where the commands (and the Python module) add
// it; apps/main.cpp alone turns the error into an exit code.
void namingFile(const std::string& file, const std::string& doing,
                const std::function<void()>& work);

}  // namespace glint
