#include "scene/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <climits>
#include <cerrno>
#include <algorithm>
#include <cstring>
#include <vector>

#include "error.h"

namespace shadowlab {

namespace {

// Closes the descriptor on every way out.
struct Descriptor {
    int fd = -1;
    ~Descriptor() {
        if (fd >= 0) ::close(fd);
    }
};

std::string overLimit(const std::string& head, const std::string& size, uintmax_t maxBytes, const std::string& what) {
    return head + ": it is " + size + " bytes, over the limit of " + std::to_string(maxBytes) + " bytes for a " + what;
}

using StartCheck = std::function<void(const std::string&, uintmax_t)>;
constexpr size_t kStartBytes = 4096;

template <class Bytes>
Bytes readWhole(const std::string& path, const std::string& what, uintmax_t maxBytes, const StartCheck& checkStart = {}) {
    const std::string head = path + ": cannot read the " + what;
    // Opened once, and everything else asked of the open descriptor, so the file checked is the
    // file read (no stat-then-open race). O_NONBLOCK: opening a FIFO that has no writer returns at
    // once instead of waiting for one; O_NOCTTY: a terminal named here never becomes ours.
    Descriptor d;
    do d.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    while (d.fd < 0 && errno == EINTR);
    if (d.fd < 0) {
        if (errno == ENOENT || errno == ENOTDIR) throw InputError(head + ": no such file");
        throw InputError(head + ": " + std::strerror(errno));
    }
    struct stat st {};
    if (::fstat(d.fd, &st) != 0) throw InputError(head + ": " + std::strerror(errno));
    if (S_ISDIR(st.st_mode)) throw InputError(head + ": it is a directory (a folder), expected a file");
    if (!S_ISREG(st.st_mode)) throw InputError(head + ": it is not a regular file (a FIFO, a device or a socket)");
    if (uintmax_t(st.st_size) > maxBytes) throw InputError(overLimit(head, std::to_string(st.st_size), maxBytes, what));
    // A regular file: reads never block. Read at most one byte past the limit, so a file that grows
    // while it is read is refused instead of read without end.
    // With a start check, only the start is read (and allocated) until the check has passed.
    const size_t whole = std::min<size_t>(size_t(st.st_size), size_t(maxBytes)) + 1;
    const size_t startBytes = std::min<size_t>(kStartBytes, size_t(st.st_size));
    bool started = !checkStart;
    Bytes bytes(started ? whole : std::min(whole, kStartBytes), 0);
    size_t got = 0;
    while (true) {
        if (!started && got >= startBytes) {
            started = true;
            checkStart(std::string(reinterpret_cast<const char*>(bytes.data()), got), uintmax_t(st.st_size));
            bytes.resize(whole);
        }
        if (got == bytes.size()) {
            if (got > maxBytes) break;
            bytes.resize(std::min<size_t>(size_t(maxBytes) + 1, got + 65536));
        }
        const size_t want = started ? bytes.size() - got : std::min(bytes.size(), startBytes) - got;
        const ssize_t n = ::read(d.fd, reinterpret_cast<char*>(bytes.data()) + got, want);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw InputError(head + ": " + std::strerror(errno));
        }
        if (n == 0) break;
        got += size_t(n);
    }
    if (got > maxBytes) throw InputError(overLimit(head, "over " + std::to_string(maxBytes), maxBytes, what));
    bytes.resize(got);
    return bytes;
}

}  // namespace

std::string readInputFile(const std::string& path, const std::string& what, uintmax_t maxBytes) {
    return readWhole<std::string>(path, what, maxBytes);
}

std::vector<unsigned char> readInputBytes(const std::string& path, const std::string& what, uintmax_t maxBytes) {
    return readWhole<std::vector<unsigned char>>(path, what, maxBytes);
}

std::string readInputFile(const std::string& path, const std::string& what, uintmax_t maxBytes,
                          const std::function<void(const std::string&, uintmax_t)>& checkStart) {
    return readWhole<std::string>(path, what, maxBytes, checkStart);
}

void checkPathName(const std::string& what, const std::string& path) {
    auto shown = [&] { return path.size() > 80 ? path.substr(0, 60) + "... (" + std::to_string(path.size()) + " bytes)" : path; };
    if (path.size() >= size_t(PATH_MAX))
        throw InputError(what + ": '" + shown() + "': the path is " + std::to_string(path.size()) +
                         " bytes long, over the system's limit of " + std::to_string(PATH_MAX - 1));
    size_t start = 0;
    while (start <= path.size()) {
        size_t slash = path.find('/', start);
        if (slash == std::string::npos) slash = path.size();
        if (slash - start > size_t(NAME_MAX))
            throw InputError(what + ": '" + shown() + "': a name in the path is " + std::to_string(slash - start) +
                             " bytes long, over the file system's limit of " + std::to_string(NAME_MAX));
        start = slash + 1;
    }
}

}  // namespace shadowlab
