#pragma once
// The exception hierarchy shared by every layer. The CLI maps the kind to an exit code: what the
// user must change in the input (InputError, TopologyError, IoError) exits 2, a computation that
// failed on valid input (SolverError, InternalError) exits 3.
#include <stdexcept>
#include <string>

namespace mspline::structure {

/// Base of every mspline error; what() is one line a user can act on.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The input (file or argument) is unusable: unreadable, malformed, or violating a precondition.
class InputError : public Error {
 public:
  using Error::Error;
};

/// The mesh has the wrong topology for the requested operation (e.g. non-manifold, wrong genus).
class TopologyError : public InputError {
 public:
  using InputError::InputError;
};

/// A file could not be read or written at the operating-system level.
class IoError : public Error {
 public:
  using Error::Error;
};

/// A computation failed on valid input (no convergence, a singular system, a construction that
/// could not be completed); what() names the stage ("cone placement: ...").
class SolverError : public Error {
 public:
  using Error::Error;
};

/// An internal invariant was violated: a bug in mspline, never the user's fault.
class InternalError : public Error {
 public:
  using Error::Error;
};

[[noreturn]] void throwAssertion(const char* condition, const char* file, int line,
                                 const std::string& message);

}  // namespace mspline::structure

/// Checks an internal invariant in every build type; throws InternalError naming file:line.
#define MSPLINE_ASSERT(condition, message)                                             \
  do {                                                                                 \
    if (!(condition))                                                                  \
      ::mspline::structure::throwAssertion(#condition, __FILE__, __LINE__, (message)); \
  } while (false)
