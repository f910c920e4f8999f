// `spsm`: sub-pixel shadow maps (lecocq2014). techniques/spsm/README.md has the design.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "graph/technique.h"
#include "shared/shared.h"

namespace shadowlab {

// The branches of the look-up (shaders/spsm/branches.glsl), by value 0..8: a name and a doc line.
struct SpsmBranch {
    const char* name;
    const char* doc;
};
const std::array<SpsmBranch, 9>& spsmBranches();

// How the build rasterizes conservatively on this context: "GL_NV_conservative_raster",
// "GL_INTEL_conservative_rasterization" (the driver's, enabled per draw) or "geometry shader"
// (Hasselgren et al. 2005's bounding triangle, shaders/spsm/build.geom). Needs a current context.
std::string spsmConservativeMethod();

// The CPU mirror of the look-up (shaders/spsm/lookup.comp) for one receiver, from the stored
// triangles of the map (`words`: RGBA32UI texels, GL row order, `size` x `size`): what the --pixel
// record reports and tests compare with the GPU.
struct SpsmLookup {
    int branch = 0;             // a value of spsmBranches()
    float visibility = 1.0f;
    glm::ivec2 texel{0};        // the receiver's texel
    std::vector<glm::ivec2> tested;  // texels whose triangles were intersected, in order
    std::vector<int> results;        // spsmTriangleTest per tested texel (0 miss, 1 covers behind, 2 hit)
    unsigned occluding = 0;          // the reconstruction's 3x3 depth comparisons (bit k = (dy+1)*3+dx+1)
    bool reconstructed = false;
    shared::SpsmEdge edge{};
};
SpsmLookup spsmLookup(const std::vector<uint32_t>& words, int size, glm::vec2 x, float z, float bias, int neighbourhood,
                      bool reconstruction);

const TechniqueDesc& spsmTechnique();

}  // namespace shadowlab
