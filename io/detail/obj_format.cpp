#include "mspline/io/detail/obj_format.h"

#include <cctype>

#include "mspline/io/detail/output_buffer.h"
#include "mspline/io/detail/text_cursor.h"

namespace mspline::io::detail {

namespace {

// OBJ indices are 1-based, or relative to the end of the list so far when negative. Index 0 is
// invalid; it becomes -1 so that validation reports it as out of range.
std::int64_t resolveIndex(std::int64_t index, std::size_t countSoFar) {
  if (index > 0) return index - 1;
  if (index < 0) return static_cast<std::int64_t>(countSoFar) + index;
  return -1;
}

// Every OBJ statement is a word of letters, digits and underscores; anything else at the start
// of a line means the file is not OBJ text (for example binary data with an .obj name).
bool isStatementKeyword(std::string_view keyword) {
  if (keyword.empty() || !std::isalpha(static_cast<unsigned char>(keyword[0]))) return false;
  for (char c : keyword)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  return true;
}

bool startsIndex(char c) {
  return std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+';
}

}  // namespace

void readObj(std::string_view data, const std::string& source, structure::PolygonSoup& soup,
             std::vector<std::string>& warnings) {
  TextCursor cursor(withoutByteOrderMark(data), source, '#');
  std::vector<std::array<double, 2>> uvs;
  // The texture coordinate index of every face corner, in face order, while every corner has one.
  std::vector<std::int64_t> cornerUVIndices;
  bool everyCornerHasUV = true;

  while (cursor.skipWhitespace()) {
    std::string_view keyword = cursor.word();
    if (keyword == "v") {
      std::array<double, 3>& p = soup.positions.emplace_back();
      p[0] = cursor.number("an x coordinate");
      p[1] = cursor.number("a y coordinate");
      p[2] = cursor.number("a z coordinate");
      while (!cursor.atLineEnd()) cursor.number("a vertex weight or color");
    } else if (keyword == "vt") {
      std::array<double, 2>& uv = uvs.emplace_back();
      uv[0] = cursor.number("a u texture coordinate");
      uv[1] = cursor.atLineEnd() ? 0.0 : cursor.number("a v texture coordinate");
      while (!cursor.atLineEnd()) cursor.number("a w texture coordinate");
    } else if (keyword == "f") {
      std::vector<std::int64_t>& face = soup.faces.emplace_back();
      while (!cursor.atLineEnd()) {
        face.push_back(resolveIndex(cursor.integer("a vertex index", '/'), soup.positions.size()));
        bool hasUV = false;
        if (cursor.peek() == '/') {
          cursor.advance();
          if (cursor.peek() != '/') {
            if (!startsIndex(cursor.peek())) cursor.failExpected("a texture coordinate index");
            std::int64_t uv =
                resolveIndex(cursor.integer("a texture coordinate index", '/'), uvs.size());
            if (everyCornerHasUV) cornerUVIndices.push_back(uv);
            hasUV = true;
          }
          if (cursor.peek() == '/') {
            cursor.advance();
            if (!startsIndex(cursor.peek())) cursor.failExpected("a normal index");
            cursor.integer("a normal index");
          }
        }
        if (!hasUV && everyCornerHasUV) {
          everyCornerHasUV = false;
          cornerUVIndices.clear();
        }
      }
    } else if (!isStatementKeyword(keyword)) {
      cursor.fail("not an OBJ statement: " + quoteToken(keyword));
    }
    cursor.nextLine();
  }

  if (soup.faces.empty()) return;
  if (!everyCornerHasUV) {
    if (!uvs.empty())
      warnings.push_back("texture coordinates ignored: not every face corner has one");
    return;
  }
  for (std::int64_t index : cornerUVIndices) {
    if (index < 0 || index >= static_cast<std::int64_t>(uvs.size())) {
      warnings.push_back("texture coordinates ignored: a face refers to texture coordinate " +
                         std::to_string(index + 1) + " of " + std::to_string(uvs.size()));
      return;
    }
  }
  soup.cornerUVs.reserve(soup.faces.size());
  std::size_t corner = 0;
  for (const auto& face : soup.faces) {
    auto& faceUVs = soup.cornerUVs.emplace_back();
    faceUVs.reserve(face.size());
    for (std::size_t k = 0; k < face.size(); ++k)
      faceUVs.push_back(uvs[static_cast<std::size_t>(cornerUVIndices[corner++])]);
  }
}

void writeObj(std::ostream& out, const structure::PolygonSoup& soup, bool withUVs,
              const VertexAttributes& attributes) {
  OutputBuffer buffer(out);
  for (const auto& p : soup.positions) {
    buffer.text("v ");
    buffer.pointLine(p);
  }
  for (const auto& uv : attributes.uvs) {
    buffer.text("vt ");
    buffer.number(uv[0]);
    buffer.character(' ');
    buffer.number(uv[1]);
    buffer.character('\n');
  }
  for (const auto& n : attributes.normals) {
    buffer.text("vn ");
    buffer.pointLine(n);
  }
  const bool vertexUVs = !attributes.uvs.empty(), normals = !attributes.normals.empty();
  if (withUVs) {
    for (const auto& faceUVs : soup.cornerUVs) {
      for (const auto& uv : faceUVs) {
        buffer.text("vt ");
        buffer.number(uv[0]);
        buffer.character(' ');
        buffer.number(uv[1]);
        buffer.character('\n');
      }
    }
  }
  std::int64_t uvIndex = 1;
  for (const auto& face : soup.faces) {
    buffer.character('f');
    for (std::int64_t index : face) {
      buffer.character(' ');
      buffer.integer(index + 1);
      if (withUVs) {
        buffer.character('/');
        buffer.integer(uvIndex++);
      } else if (vertexUVs) {
        buffer.character('/');
        buffer.integer(index + 1);
      }
      if (normals) {
        buffer.text(withUVs || vertexUVs ? "/" : "//");
        buffer.integer(index + 1);
      }
    }
    buffer.character('\n');
  }
  buffer.flush();
}

void writeObjLines(std::ostream& out, const std::vector<std::array<double, 3>>& points,
                   const std::vector<std::array<std::int64_t, 2>>& segments) {
  OutputBuffer buffer(out);
  for (const auto& p : points) {
    buffer.text("v ");
    buffer.pointLine(p);
  }
  for (const auto& segment : segments) {
    buffer.text("l ");
    buffer.integer(segment[0] + 1);
    buffer.character(' ');
    buffer.integer(segment[1] + 1);
    buffer.character('\n');
  }
  buffer.flush();
}

}  // namespace mspline::io::detail
