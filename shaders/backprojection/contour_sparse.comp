// ssm-contour's visibility over the packed pixels (screen_adaptive on): visibility_sparse.glsl.
#include "visibility_common.glsl"
#include "contour_area.glsl"
#include "visibility_levels.glsl"
#include "visibility_sparse.glsl"
