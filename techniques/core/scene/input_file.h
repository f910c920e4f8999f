// The one door a reader's file comes through (issue 24, "every input checked at the door"): a
// regular file (a folder, a FIFO or a device is an error naming the path, not an endless read, a
// stream of zeros or "the file is empty"), at most a stated size for its kind, opened once and read
// whole. Used by the JSON documents (bench and figure specs, sidecars), PFM images, lessons and
// window scripts; the scene and glTF loaders have their own checks of the same kind (file.cpp,
// gltf.cpp).
#pragma once
#include <cstdint>
#include <string>

namespace shadowlab {

// Limits per kind of input (docs/robustness.md lists them).
constexpr uintmax_t kMaxTextInputBytes = uintmax_t(16) << 20;    // lessons, specs, sidecars, scripts
constexpr uintmax_t kMaxImageInputBytes = uintmax_t(1) << 30;    // a PFM (8192 x 8192 x 3 floats is 805 MB)

// The bytes of `path`, or InputError "<path>: cannot read the <what>: ..." when it does not exist,
// is not a regular file, is over `maxBytes` or fails to read.
std::string readInputFile(const std::string& path, const std::string& what, uintmax_t maxBytes);

}  // namespace shadowlab
