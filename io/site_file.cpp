#include "mspline/io/site_file.h"

#include <charconv>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/text_records.h"
#include "mspline/structure/core/whole_file.h"

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
  return parseSiteList(readWholeFile(path), path, mesh);
}

std::vector<SurfacePoint> parseSiteList(const std::string& text, const std::string& sourceName,
                                        const TriMesh& mesh) {
  const std::string& path = sourceName;
  std::vector<SurfacePoint> sites;
  for (const TextRecord& record : textRecords(text)) {
    const std::vector<std::string>& tokens = record.fields;
    const std::string where = path + ":" + std::to_string(record.line);
    SurfacePoint site;
    bool valid = tokens.size() == 4 && parseWhole(tokens[0], site.face);
    for (int k = 0; valid && k < 3; ++k) valid = parseWhole(tokens[k + 1], site.barycentric[k]);
    if (!valid)
      throw InputError(where +
                       ": expected 'face b0 b1 b2' (a face index and three barycentric "
                       "coordinates), got '" +
                       record.content + "'");
    checkSurfacePoint(mesh, site, where);
    sites.push_back(site);
  }
  if (sites.empty()) throw InputError(path + ": no sites");
  return sites;
}

}  // namespace mspline::io
