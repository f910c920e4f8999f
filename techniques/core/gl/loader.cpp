#include "gl/loader.h"

#define X(name, type) type sl_##name = nullptr;
#include "gl/functions.inc"
#undef X

namespace shadowlab {

int loadGLFunctions(GLProcLoader loader) {
    int missing = 0;
#define X(name, type)                                                  \
    sl_##name = reinterpret_cast<type>(loader(#name));                 \
    if (!sl_##name) ++missing;
#include "gl/functions.inc"
#undef X
    return missing;
}

}  // namespace shadowlab
