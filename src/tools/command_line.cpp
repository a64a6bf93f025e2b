#include "vocal/tools/command_line.h"

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>

#include "vocal/core/errors.h"

namespace vocal {

CommandLine::CommandLine(int argc, const char* const* argv, const std::set<std::string>& value_options,
                         const std::set<std::string>& switches) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.size() > 2 && arg.compare(0, 2, "--") == 0) {
      const std::string name = arg.substr(2);
      if (switches.count(name)) {
        options_.emplace_back(name, "");
      } else if (value_options.count(name)) {
        if (i + 1 >= argc) throw InputError("option --" + name + " needs a value");
        options_.emplace_back(name, argv[++i]);
      } else {
        throw InputError("unknown option --" + name);
      }
    } else {
      positional_.push_back(arg);
    }
  }
}

const std::string* CommandLine::find(const std::string& name) const {
  for (auto it = options_.rbegin(); it != options_.rend(); ++it) {
    if (it->first == name) return &it->second;
  }
  return nullptr;
}

bool CommandLine::has(const std::string& name) const { return find(name) != nullptr; }

std::string CommandLine::text(const std::string& name, const std::string& fallback) const {
  const std::string* value = find(name);
  return value ? *value : fallback;
}

double CommandLine::number(const std::string& name, double fallback) const {
  const std::string* value = find(name);
  if (!value) return fallback;
  char* end = nullptr;
  const double parsed = std::strtod(value->c_str(), &end);
  if (value->empty() || *end != '\0' || !std::isfinite(parsed)) {
    throw InputError("option --" + name + ": '" + *value + "' is not a number");
  }
  return parsed;
}

int CommandLine::integer(const std::string& name, int fallback) const {
  const std::string* value = find(name);
  if (!value) return fallback;
  char* end = nullptr;
  const long parsed = std::strtol(value->c_str(), &end, 10);
  if (value->empty() || *end != '\0' || parsed < -2147483647L || parsed > 2147483647L) {
    throw InputError("option --" + name + ": '" + *value + "' is not an integer");
  }
  return static_cast<int>(parsed);
}

int runTool(const char* name, const char* usage, int (*body)(const CommandLine&), int argc, const char* const* argv,
            const std::set<std::string>& value_options, const std::set<std::string>& switches,
            std::size_t positional_count) {
  std::set<std::string> all_switches = switches;
  all_switches.insert("help");
  std::unique_ptr<CommandLine> command_line;
  try {
    command_line = std::make_unique<CommandLine>(argc, argv, value_options, all_switches);
  } catch (const InputError& e) {
    std::cerr << name << ": error: " << e.what() << "\n" << usage;
    return 2;
  }
  if (command_line->has("help")) {
    std::cout << usage;
    return 0;
  }
  if (command_line->positional().size() != positional_count) {
    std::cerr << name << ": error: expected " << positional_count << " argument(s), got "
              << command_line->positional().size() << "\n"
              << usage;
    return 2;
  }
  try {
    return body(*command_line);
  } catch (const InputError& e) {
    std::cerr << name << ": error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << name << ": internal error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace vocal
