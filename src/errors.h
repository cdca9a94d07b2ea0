#pragma once
// Exceptions thrown by the offline parts of the core (IO, bake, decomposition).
// Hot paths (queries) never throw: they are noexcept and return a status.
#include <stdexcept>
#include <string>

namespace hb {

/// Base of every error the core throws; what() names the file or value and the cause.
class Error : public std::runtime_error {
public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

/// A file could not be opened, read or written (missing, empty, truncated, permission).
class IoError : public Error {
public:
  explicit IoError(const std::string& what) : Error(what) {}
};

/// The content of a file or an argument is invalid (garbage, NaN, bad index, corrupt box).
class InvalidInput : public Error {
public:
  explicit InvalidInput(const std::string& what) : Error(what) {}
};

/// A long operation (bake, decomposition) was cancelled through its progress callback.
class Cancelled : public Error {
public:
  explicit Cancelled(const std::string& what) : Error(what) {}
};

/// Embree or another library reported an error.
class LibraryError : public Error {
public:
  explicit LibraryError(const std::string& what) : Error(what) {}
};

} // namespace hb
