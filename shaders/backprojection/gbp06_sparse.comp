// ssm-gbp06's visibility over the packed pixels (screen_adaptive on): visibility_sparse.glsl.
#include "visibility_common.glsl"
#include "gbp06_area.glsl"
#include "visibility_levels.glsl"
#include "visibility_sparse.glsl"
