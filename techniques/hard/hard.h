#pragma once
#include "visibility/shadow_map.h"

namespace shadowlab {

// The depth-test pass of `hard`; with `pcf` true it averages an n x n kernel of tests (pcf reuses it).
PassDesc depthTestPass(bool pcf);
// `plane_test`: the depth test against the receiver's tangent plane at the tested texel
// (shadow_lookup.glsl's shadowTestPlane) instead of the slope-biased receiver depth. Off for
// `hard` (the classic test a lesson starts from), on for `reference`; a point light's `hard` takes
// the requested technique's value.
ParamDesc planeTestParam(bool on);
// The per-pixel record of --pixel for the shadow-map techniques: the receiver's texel and depths,
// and the texels the depth tests read (one texel; with `pcf` the n x n kernel around it).
InternalDesc shadowMapPixelRecord(bool pcf = false);

const TechniqueDesc& hardTechnique();

}  // namespace shadowlab
