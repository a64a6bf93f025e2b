#include "vocal/core/folders.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>

#include "vocal/core/errors.h"

namespace vocal {

void makeFolders(const std::string& path) {
  if (path.empty()) throw InputError("an empty folder path was given");
  for (std::size_t slash = path.find('/', 1);; slash = path.find('/', slash + 1)) {
    const std::string prefix = path.substr(0, slash);
    if (!prefix.empty() && ::mkdir(prefix.c_str(), 0755) != 0 && errno != EEXIST) {
      throw InputError(prefix + ": cannot create folder (" + std::strerror(errno) + ")");
    }
    if (slash == std::string::npos) break;
  }
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) throw InputError(path + ": exists and is not a folder");
}

}  // namespace vocal
