#include "mspline/structure/core/text_records.h"

#include <cctype>
#include <sstream>

namespace mspline::structure {

std::vector<TextRecord> textRecords(const std::string& text) {
  std::vector<TextRecord> records;
  std::istringstream in(text);
  std::string line;
  for (int lineNumber = 1; std::getline(in, line); ++lineNumber) {
    TextRecord record{lineNumber, line.substr(0, line.find('#')), {}};
    std::istringstream fields(record.content);
    for (std::string field; fields >> field;) record.fields.push_back(field);
    if (record.fields.empty()) continue;
    while (std::isspace(static_cast<unsigned char>(record.content.back())))
      record.content.pop_back();
    records.push_back(std::move(record));
  }
  return records;
}

}  // namespace mspline::structure
