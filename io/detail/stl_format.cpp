#include "mspline/io/detail/stl_format.h"

#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>

#include "mspline/io/detail/byte_order.h"
#include "mspline/io/detail/output_buffer.h"
#include "mspline/io/detail/text_cursor.h"

namespace mspline::io::detail {

namespace {

constexpr std::size_t kHeaderBytes = 84;
constexpr std::size_t kTriangleBytes = 50;

// STL repeats a shared vertex in every triangle that uses it; corners with bit-identical
// coordinates are the same vertex. -0 and +0 are merged too: they are the same point.
class VertexMerger {
 public:
  explicit VertexMerger(std::vector<std::array<double, 3>>& positions) : positions_(positions) {}

  void reserve(std::size_t vertices) {
    positions_.reserve(vertices);
    indices_.reserve(vertices);
  }

  std::int64_t index(double x, double y, double z) {
    Key key{{bits(x), bits(y), bits(z)}};
    auto [it, inserted] = indices_.try_emplace(key, static_cast<std::int64_t>(positions_.size()));
    if (inserted) positions_.push_back({x, y, z});
    return it->second;
  }

 private:
  struct Key {
    std::array<std::uint64_t, 3> bits;
    bool operator==(const Key& other) const { return bits == other.bits; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& key) const {
      std::uint64_t h = 0x9e3779b97f4a7c15ull;
      for (std::uint64_t b : key.bits) {
        h ^= b + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
        h *= 0xff51afd7ed558ccdull;
      }
      return static_cast<std::size_t>(h ^ (h >> 33));
    }
  };
  static std::uint64_t bits(double value) {
    double canonical = value + 0.0;  // turns -0 into +0
    std::uint64_t result;
    std::memcpy(&result, &canonical, sizeof result);
    return result;
  }

  std::vector<std::array<double, 3>>& positions_;
  std::unordered_map<Key, std::int64_t, KeyHash> indices_;
};

bool equalsIgnoringCase(std::string_view text, std::string_view keyword) {
  if (text.size() != keyword.size()) return false;
  for (std::size_t i = 0; i < text.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(text[i])) != keyword[i]) return false;
  return true;
}

bool startsAsAscii(std::string_view data) {
  std::size_t start = 0;
  while (start < data.size() && std::isspace(static_cast<unsigned char>(data[start]))) ++start;
  return equalsIgnoringCase(data.substr(start, 5), "solid");
}

// Reads the next keyword, which may be on a later line.
std::string_view nextWord(TextCursor& cursor, const char* expected) {
  if (!cursor.skipWhitespace())
    cursor.fail(std::string("file ends where '") + expected + "' was expected (truncated)");
  return cursor.word();
}

void expectWord(TextCursor& cursor, const char* expected) {
  std::string_view word = nextWord(cursor, expected);
  if (!equalsIgnoringCase(word, expected))
    cursor.fail(std::string("expected '") + expected + "', found " + quoteToken(word));
}

double nextNumber(TextCursor& cursor, const char* what) {
  if (!cursor.skipWhitespace()) cursor.failExpected(what);
  return cursor.number(what);
}

void readAscii(std::string_view data, const std::string& source, structure::PolygonSoup& soup) {
  TextCursor cursor(data, source, '\0');
  VertexMerger merger(soup.positions);
  expectWord(cursor, "solid");
  cursor.nextLine();  // the rest of the line is the solid's name
  for (;;) {
    std::string_view word = nextWord(cursor, "endsolid");
    if (equalsIgnoringCase(word, "endsolid")) {
      cursor.nextLine();
      // Several solids may follow each other; anything else after the last one is ignored.
      if (!cursor.skipWhitespace() || !equalsIgnoringCase(cursor.word(), "solid")) break;
      cursor.nextLine();
      continue;
    }
    if (!equalsIgnoringCase(word, "facet"))
      cursor.fail("expected 'facet' or 'endsolid', found " + quoteToken(word));
    expectWord(cursor, "normal");
    for (int k = 0; k < 3; ++k) nextNumber(cursor, "a normal coordinate");
    expectWord(cursor, "outer");
    expectWord(cursor, "loop");
    std::vector<std::int64_t> face;
    face.reserve(3);
    for (;;) {
      word = nextWord(cursor, "endloop");
      if (equalsIgnoringCase(word, "endloop")) break;
      if (!equalsIgnoringCase(word, "vertex"))
        cursor.fail("expected 'vertex' or 'endloop', found " + quoteToken(word));
      double x = nextNumber(cursor, "an x coordinate");
      double y = nextNumber(cursor, "a y coordinate");
      double z = nextNumber(cursor, "a z coordinate");
      face.push_back(merger.index(x, y, z));
    }
    expectWord(cursor, "endfacet");
    soup.faces.push_back(std::move(face));
  }
}

void readBinary(std::string_view data, const std::string& source, structure::PolygonSoup& soup,
                std::vector<std::string>& warnings) {
  if (data.size() < kHeaderBytes)
    failIn(source, "only " + std::to_string(data.size()) +
                       " bytes: too short for binary STL (84-byte header) and not ASCII STL");
  std::uint32_t count = decode<std::uint32_t>(data.data() + 80, false);
  std::uint64_t expected = kHeaderBytes + std::uint64_t(kTriangleBytes) * count;
  if (data.size() < expected)
    failIn(source, "binary STL declares " + std::to_string(count) + " triangles (" +
                       std::to_string(expected) + " bytes), but the file has " +
                       std::to_string(data.size()) + " bytes (truncated)");
  if (data.size() > expected)
    warnings.push_back(std::to_string(data.size() - expected) +
                       " bytes after the last STL triangle were ignored");
  VertexMerger merger(soup.positions);
  merger.reserve(count / 2 + 3);
  soup.faces.reserve(count);
  for (std::uint32_t t = 0; t < count; ++t) {
    const char* corner = data.data() + kHeaderBytes + std::size_t(kTriangleBytes) * t + 12;
    std::vector<std::int64_t>& face = soup.faces.emplace_back(3);
    for (std::int64_t& index : face) {
      index = merger.index(decode<float>(corner, false), decode<float>(corner + 4, false),
                           decode<float>(corner + 8, false));
      corner += 12;
    }
  }
}

}  // namespace

void readStl(std::string_view data, const std::string& source, structure::PolygonSoup& soup,
             std::vector<std::string>& warnings) {
  // A binary header may begin with "solid" too. A file whose size matches its triangle count
  // is binary; otherwise ASCII STL is recognised by "solid" and by containing no zero byte
  // (binary STL practically always has some, in the count or the attribute words).
  bool sizeMatchesBinary =
      data.size() >= kHeaderBytes &&
      data.size() == kHeaderBytes + std::uint64_t(kTriangleBytes) *
                                        decode<std::uint32_t>(data.data() + 80, false);
  bool ascii = !sizeMatchesBinary && startsAsAscii(data) &&
               std::memchr(data.data(), '\0', data.size()) == nullptr;
  if (ascii) {
    readAscii(data, source, soup);
  } else {
    readBinary(data, source, soup, warnings);
  }
}

void writeStl(std::ostream& out, const structure::PolygonSoup& soup) {
  if (soup.faces.size() > std::numeric_limits<std::uint32_t>::max())
    throw structure::InputError("binary STL cannot hold " + std::to_string(soup.faces.size()) +
                                " triangles");
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    if (soup.faces[f].size() != 3)
      throw structure::InputError("STL stores triangles only, but face " + std::to_string(f) +
                                  " has " + std::to_string(soup.faces[f].size()) + " vertices");
  }
  // Beyond float's range a coordinate would become infinite, which the reader refuses.
  for (std::size_t v = 0; v < soup.positions.size(); ++v)
    for (double coordinate : soup.positions[v])
      if (!(std::abs(coordinate) <= std::numeric_limits<float>::max()))
        throw structure::InputError("binary STL stores floats, but vertex " + std::to_string(v) +
                                    " has the coordinate " + std::to_string(coordinate));
  OutputBuffer buffer(out);
  // The header must not start with "solid", or readers may take the file for ASCII STL.
  std::string header = "binary STL written by mspline";
  header.resize(80, ' ');
  buffer.text(header);
  buffer.littleEndian(static_cast<std::uint32_t>(soup.faces.size()));
  for (const auto& face : soup.faces) {
    const auto& a = soup.positions[static_cast<std::size_t>(face[0])];
    const auto& b = soup.positions[static_cast<std::size_t>(face[1])];
    const auto& c = soup.positions[static_cast<std::size_t>(face[2])];
    std::array<double, 3> u{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    std::array<double, 3> v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    std::array<double, 3> n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                            u[0] * v[1] - u[1] * v[0]};
    double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (double component : n)
      buffer.littleEndian(static_cast<float>(length > 0 ? component / length : 0.0));
    for (const auto* corner : {&a, &b, &c})
      for (double coordinate : *corner) buffer.littleEndian(static_cast<float>(coordinate));
    buffer.littleEndian(std::uint16_t{0});
  }
  buffer.flush();
}

}  // namespace mspline::io::detail
