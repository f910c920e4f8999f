// The one door a reader's file comes through (issue 24, "every input checked at the door"): a
// regular file (a folder, a FIFO or a device is an error naming the path, not an endless read, a
// stream of zeros or "the file is empty"), at most a stated size for its kind, opened once and read
// whole. Used by the JSON documents (bench and figure specs, sidecars), PFM images, lessons and
// window scripts, scene files, glTF files and their buffers, reference cache entries.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace shadowlab {

// Limits per kind of input (docs/robustness.md lists them).
constexpr uintmax_t kMaxTextInputBytes = uintmax_t(16) << 20;    // lessons, specs, sidecars, scripts
constexpr uintmax_t kMaxImageInputBytes = uintmax_t(1) << 30;    // a PFM (8192 x 8192 x 3 floats is 805 MB)
constexpr uintmax_t kMaxSceneInputBytes = uintmax_t(256) << 20;  // a scene file (geometry belongs in glTF)
constexpr uintmax_t kMaxGltfInputBytes = uintmax_t(1) << 31;     // a .gltf/.glb and each of its buffers

// The bytes of `path`, or InputError "<path>: cannot read the <what>: ..." when it does not exist,
// is not a regular file, is over `maxBytes` or fails to read.
// Opened once (O_NONBLOCK, so a FIFO never blocks), checked on the open descriptor, read whole;
// a file that grows past `maxBytes` while being read is refused too.
std::string readInputFile(const std::string& path, const std::string& what, uintmax_t maxBytes);
std::vector<unsigned char> readInputBytes(const std::string& path, const std::string& what, uintmax_t maxBytes);
// The same, and `checkStart(start, fileBytes)` sees the file's first bytes (up to 4 KB) and its size
// before the rest is read: a header that asks for more (or less) than the file holds is refused
// without reading gigabytes (a PFM header of 30000x30000 on a sparse file was read whole).
std::string readInputFile(const std::string& path, const std::string& what, uintmax_t maxBytes,
                          const std::function<void(const std::string& start, uintmax_t fileBytes)>& checkStart);

// InputError "<what>: ... is N bytes long ..." when `path` cannot name a file on this system: a name
// in it over NAME_MAX (255) bytes or the whole over PATH_MAX - 1 bytes. Every output check calls it
// first: the file system refuses such a path with ENAMETOOLONG, which std::filesystem's throwing
// calls turned into "internal error: filesystem error: status: File name too long" (exit 1; found by
// fuzz_cli with `viz --out /dev/111...1nu...`).
void checkPathName(const std::string& what, const std::string& path);

}  // namespace shadowlab
