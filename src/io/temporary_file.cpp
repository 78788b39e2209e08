#include "jamsim/io/temporary_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace jamsim {

std::string make_temporary_beside(const std::string& path) {
    const std::string suffix = ".tmp";
    std::string name = path + ".XXXXXX" + suffix;
    std::vector<char> buffer(name.begin(), name.end());
    buffer.push_back('\0');
    const int fd = ::mkstemps(buffer.data(), static_cast<int>(suffix.size()));
    if (fd < 0)
        throw std::runtime_error("cannot write beside '" + path + "' (a temporary file there: " + std::strerror(errno) +
                                 ")");
    // mkstemps makes the file for its owner alone (0600); the output gets the mode any new
    // file gets here (0666 less the umask), as it had before it was written through this name.
    const mode_t mask = ::umask(0);
    ::umask(mask);
    (void)::fchmod(fd, 0666 & ~mask);
    ::close(fd);
    return std::string(buffer.data());
}

}  // namespace jamsim
