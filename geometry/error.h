// glint — the one error vocabulary. What went wrong decides the exit code, and apps/main.cpp
// maps it once: bad input → 2, a render or comparison that could not be done → 1.
//
// Header-only, in geometry/ because that is the lowest room: every room that reports a user
// error (geometry's accelerator names, renderer's settings, image/, scenes/, apps/) must see it,
// the project's layout has no room of shared utilities, and a base class needs nothing to link.
#pragma once

#include <stdexcept>
#include <string>

namespace glint {

enum class ErrorKind {
  BadInput,  // the user's files, options or settings cannot work: exit code 2
  Failure,   // valid input, but the work could not be done (a failed write): exit code 1
};

// Base of every error glint reports to the user. what() is the one-line message main prints
// after "glint: "; it names where the input was wrong (file and JSON pointer, file:line, or the
// option).
class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
  ErrorKind kind() const { return kind_; }                               // what went wrong
  int exitCode() const { return kind_ == ErrorKind::BadInput ? 2 : 1; }  // main's exit code

 private:
  ErrorKind kind_;
};

// Bad input: exit code 2.
class InputError : public Error {
 public:
  explicit InputError(const std::string& message) : Error(ErrorKind::BadInput, message) {}
};

// A render, write or comparison that failed on valid input: exit code 1.
class FailureError : public Error {
 public:
  explicit FailureError(const std::string& message) : Error(ErrorKind::Failure, message) {}
};

}  // namespace glint
