#include "scene/input_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "error.h"

namespace shadowlab {

std::string readInputFile(const std::string& path, const std::string& what, uintmax_t maxBytes) {
    namespace fs = std::filesystem;
    const std::string head = path + ": cannot read the " + what;
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (ec || !fs::exists(status)) throw InputError(head + ": no such file");
    if (fs::is_directory(status)) throw InputError(head + ": it is a folder, expected a file");
    if (!fs::is_regular_file(status)) throw InputError(head + ": it is not a regular file (a FIFO, a device or a socket)");
    const uintmax_t size = fs::file_size(path, ec);
    if (ec) throw InputError(head + ": " + ec.message());
    if (size > maxBytes)
        throw InputError(head + ": it is " + std::to_string(size) + " bytes, over the limit of " + std::to_string(maxBytes) +
                         " bytes for a " + what);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(head + ": " + std::strerror(errno));
    std::string bytes(size_t(size), '\0');
    in.read(bytes.data(), std::streamsize(size));
    if (in.gcount() != std::streamsize(size)) throw InputError(head + ": it changed while being read");
    return bytes;
}

}  // namespace shadowlab
