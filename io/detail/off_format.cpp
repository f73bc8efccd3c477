#include "mspline/io/detail/off_format.h"

#include <algorithm>
#include <cctype>

#include "mspline/io/detail/output_buffer.h"
#include "mspline/io/detail/text_cursor.h"

namespace mspline::io::detail {

namespace {

// The keyword is [ST][C][N][4][n]OFF; the prefixes only add numbers to each vertex line, which
// the reader skips, except 4 (homogeneous coordinates) and n (a dimension line).
struct OffHeader {
  bool homogeneous = false;
  bool explicitDimension = false;
};

bool endsWithOff(std::string_view keyword) {
  if (keyword.size() < 3) return false;
  std::string_view tail = keyword.substr(keyword.size() - 3);
  return std::equal(tail.begin(), tail.end(), "OFF", [](char a, char b) {
    return std::toupper(static_cast<unsigned char>(a)) == b;
  });
}

OffHeader parseKeyword(TextCursor& cursor) {
  if (!cursor.skipWhitespace()) cursor.fail("the file holds only comments, no OFF header");
  std::string_view keyword = cursor.word();
  if (!endsWithOff(keyword))
    cursor.fail("expected the OFF header keyword, found " + quoteToken(keyword));
  OffHeader header;
  for (char c : keyword.substr(0, keyword.size() - 3)) {
    if (c == '4') {
      header.homogeneous = true;
    } else if (c == 'n') {
      header.explicitDimension = true;
    } else if (c != 'S' && c != 'T' && c != 'C' && c != 'N') {
      cursor.fail("unknown OFF variant " + quoteToken(keyword));
    }
  }
  return header;
}

// Moves to the next number of the header, which may be on this line or a later one.
void toNextHeaderValue(TextCursor& cursor, const char* what) {
  if (cursor.atLineEnd() && !cursor.skipWhitespace())
    cursor.fail(std::string("file ends before the header's ") + what);
}

std::int64_t headerCount(TextCursor& cursor, const char* what) {
  toNextHeaderValue(cursor, what);
  std::int64_t count = cursor.integer(what);
  if (count < 0) cursor.fail(std::string("negative ") + what + " " + std::to_string(count));
  return count;
}

}  // namespace

void readOff(std::string_view data, const std::string& source, structure::PolygonSoup& soup,
             std::vector<std::string>& /*warnings*/) {
  TextCursor cursor(withoutByteOrderMark(data), source, '#');
  OffHeader header = parseKeyword(cursor);
  if (header.explicitDimension) {
    toNextHeaderValue(cursor, "dimension");
    std::int64_t dimension = cursor.integer("the dimension");
    if (dimension != 3)
      cursor.fail("only 3-dimensional OFF is supported, the header says " +
                  std::to_string(dimension));
  }
  if (!cursor.atLineEnd() && std::isalpha(static_cast<unsigned char>(cursor.peek()))) {
    std::string_view next = cursor.word();
    if (next == "BINARY") cursor.fail("binary OFF is not supported; convert it to ASCII OFF");
    cursor.fail("expected the vertex count, found " + quoteToken(next));
  }
  std::int64_t vertexCount = headerCount(cursor, "vertex count");
  std::int64_t faceCount = headerCount(cursor, "face count");
  if (!cursor.atLineEnd()) headerCount(cursor, "edge count");  // unused, and often wrong
  if (!cursor.atLineEnd()) cursor.failExpected("the end of the header line");

  // A vertex needs at least "0 0 0\n" and a face "0\n"; a header asking for more than the file
  // can hold is rejected before anything is allocated for it.
  auto available = static_cast<std::int64_t>(cursor.remaining());
  if (vertexCount > available || faceCount > available ||
      6 * vertexCount + 2 * faceCount > available + 1)
    cursor.fail("the header declares " + std::to_string(vertexCount) + " vertices and " +
                std::to_string(faceCount) + " faces, but only " + std::to_string(available) +
                " bytes follow (truncated file or wrong header)");
  cursor.nextLine();

  soup.positions.reserve(static_cast<std::size_t>(vertexCount));
  for (std::int64_t v = 0; v < vertexCount; ++v) {
    if (!cursor.skipWhitespace())
      cursor.fail("file ends after " + std::to_string(v) + " of " + std::to_string(vertexCount) +
                  " vertices (truncated)");
    std::array<double, 3>& p = soup.positions.emplace_back();
    p[0] = cursor.number("an x coordinate");
    p[1] = cursor.number("a y coordinate");
    p[2] = cursor.number("a z coordinate");
    if (header.homogeneous) {
      double w = cursor.number("a homogeneous w coordinate");
      for (double& c : p) c /= w;
    }
    while (!cursor.atLineEnd()) cursor.number("a vertex attribute (color, normal or uv)");
    cursor.nextLine();
  }

  soup.faces.reserve(static_cast<std::size_t>(faceCount));
  for (std::int64_t f = 0; f < faceCount; ++f) {
    if (!cursor.skipWhitespace())
      cursor.fail("file ends after " + std::to_string(f) + " of " + std::to_string(faceCount) +
                  " faces (truncated)");
    std::int64_t size = cursor.integer("a face's vertex count");
    if (size < 0) cursor.fail("negative face vertex count " + std::to_string(size));
    if (size > static_cast<std::int64_t>(cursor.remaining()))
      cursor.fail("face declares " + std::to_string(size) +
                  " vertices, more than the rest of the file holds");
    std::vector<std::int64_t> face(static_cast<std::size_t>(size));
    for (std::int64_t& index : face) index = cursor.integer("a vertex index");
    while (!cursor.atLineEnd()) cursor.number("a face color value");
    cursor.nextLine();
    soup.faces.push_back(std::move(face));
  }
}

void writeOff(std::ostream& out, const structure::PolygonSoup& soup) {
  OutputBuffer buffer(out);
  buffer.text("OFF\n");
  buffer.integer(static_cast<std::int64_t>(soup.positions.size()));
  buffer.character(' ');
  buffer.integer(static_cast<std::int64_t>(soup.faces.size()));
  buffer.text(" 0\n");
  for (const auto& p : soup.positions) {
    buffer.pointLine(p);
  }
  for (const auto& face : soup.faces) {
    buffer.countedIndexLine(face);
  }
  buffer.flush();
}

}  // namespace mspline::io::detail
