// glint tests — checking SceneErrors: the error a call throws, and its file, pointer and
// message in one assertion.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "scenes/errors.h"

namespace glint::test {

// The SceneError `f` throws (a test failure when it throws nothing).
inline SceneError errorFrom(const std::function<void()>& f) {
  try {
    f();
  } catch (const SceneError& e) {
    return e;
  }
  ADD_FAILURE() << "expected a SceneError";
  return SceneError({"<none>", ""}, "<no error>");
}

}  // namespace glint::test

// The error's location is exactly (file, pointer) and its message contains `phrase`.
#define EXPECT_SCENE_ERROR(error, expectedFile, expectedPointer, phrase)  \
  do {                                                                    \
    const ::glint::SceneError& e_ = (error);                              \
    EXPECT_EQ(e_.where().file, expectedFile) << e_.what();                \
    EXPECT_EQ(e_.where().pointer, expectedPointer) << e_.what();          \
    EXPECT_NE(e_.message().find(phrase), std::string::npos) << e_.what(); \
  } while (0)
