#pragma once
// The line-based text layout shared by TUM's rgb.txt, depth.txt and trajectory files: '#' starts a
// comment line, fields are separated by white space, the first field is a timestamp in seconds.

#include <string>
#include <vector>

namespace vocal {

struct TumTextLine {
  int line_number = 0;  // 1-based, as editors show it
  std::vector<std::string> fields;
};

// Reads the data lines of `path`; throws InputError if the file cannot be read.
std::vector<TumTextLine> readTumTextLines(const std::string& path);

// "path:line: problem", the form every parse error of these files takes.
std::string tumLineError(const std::string& path, int line_number, const std::string& problem);

// Parses a finite floating-point field or throws InputError naming path, line and field.
double parseTumNumber(const std::string& path, const TumTextLine& line, std::size_t field_index,
                      const char* field_name);

// Throws InputError naming the line if `stamp` is not after `previous_stamp`.
void requireIncreasingStamp(const std::string& path, const TumTextLine& line, double previous_stamp,
                            double stamp);

}  // namespace vocal
