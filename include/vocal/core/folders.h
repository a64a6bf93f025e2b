#pragma once
// Output folders: created with their missing parents (like mkdir -p) before a tool starts its work,
// so a bad path fails at once rather than after a long run.

#include <string>

namespace vocal {

// Throws InputError naming the first part of the path that cannot be created, and why.
void makeFolders(const std::string& path);

}  // namespace vocal
