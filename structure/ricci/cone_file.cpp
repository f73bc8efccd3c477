#include "mspline/structure/ricci/cone_file.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>
#include <sstream>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/text_records.h"
#include "mspline/structure/core/whole_file.h"

namespace mspline::structure {

namespace {

// The whole token as a number, or false (strtol/strtod also report partial parses like "3x").
bool parseVertex(const std::string& token, int& value) {
  if (token.empty() || token[0] == '-' || token[0] == '+') return false;
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(token.c_str(), &end, 10);
  if (errno != 0 || *end != '\0' || v > std::numeric_limits<int>::max()) return false;
  value = static_cast<int>(v);
  return true;
}

bool parseCurvature(const std::string& token, double& value) {
  errno = 0;
  char* end = nullptr;
  value = std::strtod(token.c_str(), &end);
  return !token.empty() && errno == 0 && *end == '\0' && std::isfinite(value);
}

}  // namespace

std::vector<Cone> parseConeList(const std::string& text, const std::string& sourceName) {
  std::vector<Cone> cones;
  std::set<int> seen;
  for (const TextRecord& record : textRecords(text)) {
    const std::vector<std::string>& tokens = record.fields;
    const std::string where = sourceName + ":" + std::to_string(record.line) + ": ";
    Cone cone;
    if (tokens.size() != 2 || !parseVertex(tokens[0], cone.vertex) ||
        !parseCurvature(tokens[1], cone.curvature))
      throw InputError(where +
                       "expected '<vertex> <curvature>' (a vertex index >= 0 and a "
                       "curvature in radians), got '" +
                       record.content + "'");
    if (!seen.insert(cone.vertex).second)
      throw InputError(where + "vertex " + std::to_string(cone.vertex) + " is listed twice");
    cones.push_back(cone);
  }
  return cones;
}

std::vector<Cone> readConeFile(const std::string& path) {
  return parseConeList(readWholeFile(path), path);
}

std::string formatConeFile(const std::vector<Cone>& cones) {
  std::ostringstream out;
  out.precision(17);
  out << "# mspline cones: <vertex> <curvature in radians> (2 pi - cone angle)\n";
  for (const Cone& c : cones) out << c.vertex << ' ' << c.curvature << '\n';
  return out.str();
}

}  // namespace mspline::structure
