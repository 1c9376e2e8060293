#include "cli/paths.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstring>

namespace glcast::cli {

std::string absolute_path(const std::string& path) {
    if (path.empty() || path[0] == '/') return path;
    char cwd[PATH_MAX];
    if (!getcwd(cwd, sizeof cwd)) return path;
    return std::string(cwd) + "/" + path;
}

std::string relative_to(const std::string& file, const std::string& path) {
    if (path.empty() || path[0] == '/') return path;
    const size_t slash = file.rfind('/');
    return absolute_path(slash == std::string::npos ? path : file.substr(0, slash + 1) + path);
}

bool make_directories(const std::string& dir, std::string& error) {
    for (size_t end = 1; end <= dir.size(); ++end) {
        if (end != dir.size() && dir[end] != '/') continue;
        const std::string part = dir.substr(0, end);
        if (mkdir(part.c_str(), 0755) == 0 || errno == EEXIST) continue;
        error = "cannot create " + part + ": " + std::strerror(errno);
        return false;
    }
    struct stat st {};
    if (stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) {
        error = dir + " is not a directory";
        return false;
    }
    return true;
}

}  // namespace glcast::cli
