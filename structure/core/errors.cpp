#include "mspline/structure/core/errors.h"

namespace mspline::structure {

void throwAssertion(const char* condition, const char* file, int line, const std::string& message) {
  throw InternalError(std::string(file) + ":" + std::to_string(line) + ": assertion '" + condition +
                      "' failed: " + message);
}

}  // namespace mspline::structure
