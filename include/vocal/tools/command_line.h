#pragma once
// A small argument parser for vocal's tools: positional arguments plus `--name value` options and
// `--name` switches. Errors are InputError naming the option.

#include <set>
#include <string>
#include <vector>

namespace vocal {

class CommandLine {
 public:
  // Throws InputError for an unknown option or an option missing its value.
  CommandLine(int argc, const char* const* argv, const std::set<std::string>& value_options,
              const std::set<std::string>& switches);

  const std::vector<std::string>& positional() const { return positional_; }
  bool has(const std::string& name) const;
  std::string text(const std::string& name, const std::string& fallback) const;
  double number(const std::string& name, double fallback) const;
  int integer(const std::string& name, int fallback) const;

 private:
  const std::string* find(const std::string& name) const;
  std::vector<std::string> positional_;
  std::vector<std::pair<std::string, std::string>> options_;
};

// Runs a tool's body, printing InputError and other exceptions as one line `NAME: error: ...` and
// returning the exit code (0 ok, 1 error, 2 usage error).
int runTool(const char* name, const char* usage, int (*body)(const CommandLine&), int argc, const char* const* argv,
            const std::set<std::string>& value_options, const std::set<std::string>& switches,
            std::size_t positional_count);

}  // namespace vocal
