#include "mspline/io/site_file.h"

#include <charconv>
#include <fstream>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/text_records.h"

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
  // Line by line: a read error (e.g. the path is a directory) sets badbit, as rdbuf() does not.
  std::string text;
  for (std::string line; std::getline(file, line);) text += line + '\n';
  if (file.bad()) throw IoError(path + ": error while reading the sites file");
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
