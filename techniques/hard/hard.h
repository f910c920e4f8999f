#pragma once
#include "visibility/shadow_map.h"

namespace shadowlab {

// The depth-test pass of `hard`; with `pcf` true it averages an n x n kernel of tests (pcf reuses it).
PassDesc depthTestPass(bool pcf);
// The per-pixel record of --pixel for the shadow-map techniques: the receiver's texel and depths,
// and the texels the depth tests read (one texel; with `pcf` the n x n kernel around it).
InternalDesc shadowMapPixelRecord(bool pcf = false);

const TechniqueDesc& hardTechnique();

}  // namespace shadowlab
