#include "mspline/io/site_file.h"

#include <charconv>
#include <fstream>
#include <sstream>

#include "mspline/structure/core/errors.h"

namespace mspline::io {

namespace {

using namespace structure;

template <typename Number>
bool parseWhole(const std::string& token, Number& value) {
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, value);
  return result.ec == std::errc() && result.ptr == end;
}

}  // namespace

std::vector<SurfacePoint> readSiteFile(const std::string& path, const TriMesh& mesh) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw IoError(path + ": cannot open the sites file");
  std::vector<SurfacePoint> sites;
  std::string line;
  for (int lineNumber = 1; std::getline(file, line); ++lineNumber) {
    const std::string content = line.substr(0, line.find('#'));
    std::istringstream fields(content);
    std::vector<std::string> tokens;
    for (std::string token; fields >> token;) tokens.push_back(token);
    if (tokens.empty()) continue;
    const std::string where = path + ":" + std::to_string(lineNumber);
    SurfacePoint site;
    bool valid = tokens.size() == 4 && parseWhole(tokens[0], site.face);
    for (int k = 0; valid && k < 3; ++k) valid = parseWhole(tokens[k + 1], site.barycentric[k]);
    if (!valid)
      throw InputError(where +
                       ": expected 'face b0 b1 b2' (a face index and three barycentric "
                       "coordinates), got '" +
                       content.substr(0, content.find_last_not_of(" \t\r") + 1) + "'");
    checkSurfacePoint(mesh, site, where);
    sites.push_back(site);
  }
  if (file.bad()) throw IoError(path + ": error while reading the sites file");
  if (sites.empty()) throw InputError(path + ": no sites");
  return sites;
}

}  // namespace mspline::io
