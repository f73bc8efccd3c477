#include "mspline/io/detail/ply_format.h"

#include <cmath>
#include <limits>

#include "mspline/io/detail/byte_order.h"
#include "mspline/io/detail/output_buffer.h"
#include "mspline/io/detail/text_cursor.h"

namespace mspline::io::detail {

namespace {

enum class PlyType { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

std::size_t byteSize(PlyType type) {
  switch (type) {
    case PlyType::Int8:
    case PlyType::Uint8:
      return 1;
    case PlyType::Int16:
    case PlyType::Uint16:
      return 2;
    case PlyType::Int32:
    case PlyType::Uint32:
    case PlyType::Float32:
      return 4;
    case PlyType::Float64:
      return 8;
  }
  return 8;
}

bool isFloatingPoint(PlyType type) {
  return type == PlyType::Float32 || type == PlyType::Float64;
}

bool parseType(std::string_view name, PlyType& type) {
  struct Named {
    std::string_view name;
    PlyType type;
  };
  static const Named names[] = {
      {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::Uint8},
      {"uint8", PlyType::Uint8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
      {"ushort", PlyType::Uint16},  {"uint16", PlyType::Uint16},   {"int", PlyType::Int32},
      {"int32", PlyType::Int32},    {"uint", PlyType::Uint32},     {"uint32", PlyType::Uint32},
      {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
      {"float64", PlyType::Float64}};
  for (const Named& named : names) {
    if (named.name == name) {
      type = named.type;
      return true;
    }
  }
  return false;
}

enum class Encoding { Ascii, LittleEndian, BigEndian };

struct Property {
  std::string name;
  PlyType type = PlyType::Float64;
  bool isList = false;
  PlyType countType = PlyType::Uint8;
};

// What the reader does with a property of the vertex or face element.
enum class Role { Skip, X, Y, Z, FaceIndices };

struct Element {
  std::string name;
  std::int64_t count = 0;
  std::vector<Property> properties;
  std::vector<Role> roles;
};

struct Header {
  Encoding encoding = Encoding::Ascii;
  std::vector<Element> elements;
};

Header parseHeader(TextCursor& cursor) {
  Header header;
  if (cursor.word() != "ply" || !cursor.atLineEnd())
    cursor.fail("not a PLY file: the first line must be 'ply'");
  cursor.nextLine();
  bool formatSeen = false;
  for (;;) {
    if (!cursor.skipWhitespace()) cursor.fail("the PLY header has no end_header line");
    std::string_view keyword = cursor.word();
    if (keyword == "end_header") {
      cursor.nextLine();
      break;
    }
    if (keyword == "comment" || keyword == "obj_info") {
      cursor.nextLine();
      continue;
    }
    if (keyword == "format") {
      std::string_view encoding = cursor.word();
      if (encoding == "ascii") {
        header.encoding = Encoding::Ascii;
      } else if (encoding == "binary_little_endian") {
        header.encoding = Encoding::LittleEndian;
      } else if (encoding == "binary_big_endian") {
        header.encoding = Encoding::BigEndian;
      } else {
        cursor.fail("unknown PLY format " + quoteToken(encoding));
      }
      cursor.number("the format version");
      formatSeen = true;
    } else if (keyword == "element") {
      Element& element = header.elements.emplace_back();
      element.name = std::string(cursor.word());
      if (element.name.empty()) cursor.failExpected("an element name");
      element.count = cursor.integer("the element count");
      if (element.count < 0) cursor.fail("negative element count " + std::to_string(element.count));
    } else if (keyword == "property") {
      if (header.elements.empty()) cursor.fail("a property before any element");
      Property property;
      std::string_view type = cursor.word();
      if (type == "list") {
        property.isList = true;
        std::string_view countType = cursor.word();
        if (!parseType(countType, property.countType) || isFloatingPoint(property.countType))
          cursor.fail("invalid list count type " + quoteToken(countType));
        type = cursor.word();
      }
      if (!parseType(type, property.type)) cursor.fail("unknown property type " + quoteToken(type));
      property.name = std::string(cursor.word());
      if (property.name.empty()) cursor.failExpected("a property name");
      header.elements.back().properties.push_back(std::move(property));
    } else {
      cursor.fail("unknown PLY header line starting with " + quoteToken(keyword));
    }
    if (!cursor.atLineEnd()) cursor.failExpected("the end of the header line");
    cursor.nextLine();
  }
  if (!formatSeen) cursor.fail("the PLY header has no format line");
  return header;
}

// Marks the properties the reader keeps and checks the vertex and face elements have them.
void assignRoles(Header& header, const std::string& source) {
  bool vertexSeen = false;
  for (Element& element : header.elements) {
    element.roles.assign(element.properties.size(), Role::Skip);
    if (element.name == "vertex") {
      vertexSeen = true;
      for (const char* axis : {"x", "y", "z"}) {
        bool found = false;
        for (std::size_t k = 0; k < element.properties.size(); ++k) {
          if (element.properties[k].name != axis) continue;
          if (element.properties[k].isList)
            failIn(source, std::string("property ") + axis + " is a list");
          element.roles[k] = axis[0] == 'x' ? Role::X : axis[0] == 'y' ? Role::Y : Role::Z;
          found = true;
        }
        if (!found) failIn(source, std::string("the vertex element has no property ") + axis);
      }
    } else if (element.name == "face") {
      bool found = false;
      for (std::size_t k = 0; k < element.properties.size() && !found; ++k) {
        const Property& property = element.properties[k];
        if (property.isList &&
            (property.name == "vertex_indices" || property.name == "vertex_index")) {
          element.roles[k] = Role::FaceIndices;
          found = true;
        }
      }
      if (!found && element.count > 0)
        failIn(source, "the face element has no vertex_indices list");
    }
  }
  if (!vertexSeen) failIn(source, "the PLY header declares no vertex element");
}

// Rejects counts the data cannot hold before anything is reserved for them. A binary element
// needs at least its scalar sizes and list counts, an ASCII one about two bytes per property.
void checkCountsFit(const Header& header, std::size_t dataBytes, const std::string& source) {
  std::size_t left = dataBytes + 1;
  for (const Element& element : header.elements) {
    std::size_t least = 0;
    for (const Property& property : element.properties) {
      if (header.encoding == Encoding::Ascii) {
        least += 2;
      } else {
        least += byteSize(property.isList ? property.countType : property.type);
      }
    }
    if (least == 0) continue;
    auto count = static_cast<std::size_t>(element.count);
    if (count > left / least)
      failIn(source, "the header declares " + std::to_string(element.count) + " " + element.name +
                         " elements, but only " + std::to_string(dataBytes) +
                         " bytes of data follow (truncated file or wrong header)");
    left -= count * least;
  }
}

// Indices stored as float or double must still be whole numbers.
bool wholeNumber(double value, std::int64_t& index) {
  if (!(std::abs(value) < 9.0e18) || value != std::floor(value)) return false;
  index = static_cast<std::int64_t>(value);
  return true;
}

class BinaryReader {
 public:
  BinaryReader(std::string_view data, bool bigEndian, const std::string& source)
      : p_(data.data()), end_(data.data() + data.size()), bigEndian_(bigEndian), source_(source) {}

  void setContext(const Element& element, std::int64_t index) {
    element_ = &element;
    index_ = index;
  }
  void require(std::size_t bytes) const {
    if (static_cast<std::size_t>(end_ - p_) < bytes)
      failIn(source_, "file ends inside " + element_->name + " " + std::to_string(index_) + " of " +
                          std::to_string(element_->count) + " (truncated)");
  }
  void skip(std::size_t bytes) {
    require(bytes);
    p_ += bytes;
  }
  double real(PlyType type) {
    require(byteSize(type));
    double value = 0;
    switch (type) {
      case PlyType::Float32:
        value = decode<float>(p_, bigEndian_);
        break;
      case PlyType::Float64:
        value = decode<double>(p_, bigEndian_);
        break;
      default:
        value = static_cast<double>(integerBits(type));
    }
    p_ += byteSize(type);
    return value;
  }
  std::int64_t integer(PlyType type) {
    if (isFloatingPoint(type)) {
      std::int64_t index = 0;
      if (!wholeNumber(real(type), index))
        failIn(source_, location() + ": an index is not an integer");
      return index;
    }
    require(byteSize(type));
    std::int64_t value = integerBits(type);
    p_ += byteSize(type);
    return value;
  }
  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }
  std::string location() const { return element_->name + " " + std::to_string(index_); }

 private:
  std::int64_t integerBits(PlyType type) const {
    switch (type) {
      case PlyType::Int8:
        return decode<std::int8_t>(p_, bigEndian_);
      case PlyType::Uint8:
        return decode<std::uint8_t>(p_, bigEndian_);
      case PlyType::Int16:
        return decode<std::int16_t>(p_, bigEndian_);
      case PlyType::Uint16:
        return decode<std::uint16_t>(p_, bigEndian_);
      case PlyType::Int32:
        return decode<std::int32_t>(p_, bigEndian_);
      case PlyType::Uint32:
        return decode<std::uint32_t>(p_, bigEndian_);
      default:
        return 0;
    }
  }

  const char* p_;
  const char* end_;
  bool bigEndian_;
  const std::string& source_;
  const Element* element_ = nullptr;
  std::int64_t index_ = 0;
};

void readBinary(const Header& header, std::string_view data, const std::string& source,
                structure::PolygonSoup& soup) {
  BinaryReader reader(data, header.encoding == Encoding::BigEndian, source);
  for (const Element& element : header.elements) {
    if (element.properties.empty()) continue;
    if (element.name == "vertex") soup.positions.reserve(static_cast<std::size_t>(element.count));
    if (element.name == "face") soup.faces.reserve(static_cast<std::size_t>(element.count));
    for (std::int64_t i = 0; i < element.count; ++i) {
      reader.setContext(element, i);
      std::array<double, 3>* position =
          element.name == "vertex" ? &soup.positions.emplace_back() : nullptr;
      for (std::size_t k = 0; k < element.properties.size(); ++k) {
        const Property& property = element.properties[k];
        Role role = element.roles[k];
        if (property.isList) {
          std::int64_t count = reader.integer(property.countType);
          if (count < 0) failIn(source, reader.location() + " has a negative list length");
          std::size_t bytes = static_cast<std::size_t>(count) * byteSize(property.type);
          reader.require(bytes);
          if (role != Role::FaceIndices) {
            reader.skip(bytes);
            continue;
          }
          std::vector<std::int64_t>& face =
              soup.faces.emplace_back(static_cast<std::size_t>(count));
          for (std::int64_t& index : face) index = reader.integer(property.type);
        } else if (role == Role::Skip) {
          reader.skip(byteSize(property.type));
        } else {
          (*position)[static_cast<int>(role) - static_cast<int>(Role::X)] =
              reader.real(property.type);
        }
      }
    }
  }
}

void readAscii(const Header& header, TextCursor& cursor, structure::PolygonSoup& soup) {
  for (const Element& element : header.elements) {
    if (element.properties.empty()) continue;
    if (element.name == "vertex") soup.positions.reserve(static_cast<std::size_t>(element.count));
    if (element.name == "face") soup.faces.reserve(static_cast<std::size_t>(element.count));
    for (std::int64_t i = 0; i < element.count; ++i) {
      std::array<double, 3>* position =
          element.name == "vertex" ? &soup.positions.emplace_back() : nullptr;
      for (std::size_t k = 0; k < element.properties.size(); ++k) {
        if (!cursor.skipWhitespace())
          cursor.fail("file ends inside " + element.name + " " + std::to_string(i) + " of " +
                      std::to_string(element.count) + " (truncated)");
        const Property& property = element.properties[k];
        Role role = element.roles[k];
        if (property.isList) {
          std::int64_t count = cursor.integer("a list length");
          if (count < 0 || static_cast<std::size_t>(count) > cursor.remaining())
            cursor.fail("invalid list length " + std::to_string(count));
          std::vector<std::int64_t>* face =
              role == Role::FaceIndices ? &soup.faces.emplace_back() : nullptr;
          if (face) face->reserve(static_cast<std::size_t>(count));
          for (std::int64_t j = 0; j < count; ++j) {
            if (!cursor.skipWhitespace())
              cursor.fail("file ends inside " + element.name + " " + std::to_string(i) +
                          " (truncated)");
            if (!face) {
              cursor.number("a list value");
            } else if (isFloatingPoint(property.type)) {
              std::int64_t index = 0;
              if (!wholeNumber(cursor.number("a vertex index"), index))
                cursor.fail("a vertex index is not an integer");
              face->push_back(index);
            } else {
              face->push_back(cursor.integer("a vertex index"));
            }
          }
        } else if (role == Role::Skip) {
          cursor.number("a property value");
        } else {
          (*position)[static_cast<int>(role) - static_cast<int>(Role::X)] =
              cursor.number("a coordinate");
        }
      }
    }
  }
}

}  // namespace

void readPly(std::string_view data, const std::string& source, structure::PolygonSoup& soup,
             std::vector<std::string>& /*warnings*/) {
  TextCursor cursor(data, source, '\0');
  Header header = parseHeader(cursor);
  assignRoles(header, source);
  checkCountsFit(header, cursor.remaining(), source);
  if (header.encoding == Encoding::Ascii) {
    readAscii(header, cursor, soup);
  } else {
    readBinary(header, data.substr(static_cast<std::size_t>(cursor.position() - data.data())),
               source, soup);
  }
}

void writePly(std::ostream& out, const structure::PolygonSoup& soup, bool binary,
              const VertexAttributes& attributes) {
  if (soup.positions.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw structure::InputError("PLY int indices cannot address " +
                                std::to_string(soup.positions.size()) + " vertices");
  bool smallFaces = true;
  for (const auto& face : soup.faces) smallFaces = smallFaces && face.size() <= 255;
  const bool normals = !attributes.normals.empty(), colors = !attributes.colors.empty();

  OutputBuffer buffer(out);
  buffer.text("ply\nformat ");
  buffer.text(binary ? "binary_little_endian" : "ascii");
  buffer.text(" 1.0\ncomment written by mspline\nelement vertex ");
  buffer.integer(static_cast<std::int64_t>(soup.positions.size()));
  buffer.text("\nproperty double x\nproperty double y\nproperty double z");
  if (normals) buffer.text("\nproperty double nx\nproperty double ny\nproperty double nz");
  if (colors) buffer.text("\nproperty uchar red\nproperty uchar green\nproperty uchar blue");
  buffer.text("\nelement face ");
  buffer.integer(static_cast<std::int64_t>(soup.faces.size()));
  buffer.text(smallFaces ? "\nproperty list uchar int vertex_indices\nend_header\n"
                         : "\nproperty list uint int vertex_indices\nend_header\n");
  for (std::size_t v = 0; v < soup.positions.size(); ++v) {
    if (binary) {
      for (double c : soup.positions[v]) buffer.littleEndian(c);
      if (normals)
        for (double c : attributes.normals[v]) buffer.littleEndian(c);
      if (colors)
        for (std::uint8_t c : attributes.colors[v]) buffer.littleEndian(c);
      continue;
    }
    const auto& p = soup.positions[v];
    if (!normals && !colors) {
      buffer.pointLine(p);
      continue;
    }
    for (std::size_t k = 0; k < 3; ++k) {
      if (k > 0) buffer.character(' ');
      buffer.number(p[k]);
    }
    if (normals)
      for (double c : attributes.normals[v]) {
        buffer.character(' ');
        buffer.number(c);
      }
    if (colors)
      for (std::uint8_t c : attributes.colors[v]) {
        buffer.character(' ');
        buffer.integer(c);
      }
    buffer.character('\n');
  }
  for (const auto& face : soup.faces) {
    if (binary) {
      if (smallFaces) {
        buffer.littleEndian(static_cast<std::uint8_t>(face.size()));
      } else {
        buffer.littleEndian(static_cast<std::uint32_t>(face.size()));
      }
      for (std::int64_t index : face) buffer.littleEndian(static_cast<std::int32_t>(index));
    } else {
      buffer.countedIndexLine(face);
    }
  }
  buffer.flush();
}

}  // namespace mspline::io::detail
