#include "vocal/core/tum_text_file.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "vocal/core/errors.h"

namespace vocal {

std::vector<TumTextLine> readTumTextLines(const std::string& path) {
  std::ifstream file(path);
  if (!file) {
    throw InputError(path + ": cannot open file (" + std::strerror(errno) + ")");
  }
  std::vector<TumTextLine> lines;
  std::string text;
  int line_number = 0;
  while (std::getline(file, text)) {
    ++line_number;
    const auto first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos || text[first] == '#') {
      continue;
    }
    TumTextLine line;
    line.line_number = line_number;
    std::istringstream fields(text);
    for (std::string field; fields >> field;) {
      line.fields.push_back(field);
    }
    lines.push_back(std::move(line));
  }
  if (file.bad()) {
    throw InputError(path + ": read error after line " + std::to_string(line_number));
  }
  return lines;
}

std::string tumLineError(const std::string& path, int line_number, const std::string& problem) {
  return path + ":" + std::to_string(line_number) + ": " + problem;
}

double parseTumNumber(const std::string& path, const TumTextLine& line, std::size_t field_index,
                      const char* field_name) {
  const std::string& text = line.fields.at(field_index);
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !std::isfinite(value)) {
    throw InputError(tumLineError(path, line.line_number,
                                  std::string(field_name) + " '" + text + "' is not a finite number"));
  }
  return value;
}

void requireIncreasingStamp(const std::string& path, const TumTextLine& line, double previous_stamp,
                            double stamp) {
  if (stamp <= previous_stamp) {
    std::ostringstream problem;
    problem << std::fixed << std::setprecision(6) << "timestamp " << stamp << " is not after the previous one ("
            << previous_stamp << "): stamps must be strictly increasing";
    throw InputError(tumLineError(path, line.line_number, problem.str()));
  }
}

}  // namespace vocal
