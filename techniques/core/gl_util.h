// The GL helpers in one include: formats and memory counters (gl_format.h), buffers and vertex
// arrays (gl_buffer.h), textures, framebuffers and read-back (gl_texture.h), shader programs,
// compute and the program cache (gl_program.h), per-pass pipeline state (gl_state.h).
#pragma once
#include "gl_buffer.h"
#include "gl_format.h"
#include "gl_program.h"
#include "gl_state.h"
#include "gl_texture.h"

namespace shadowlab {

// One empty VAO for full-screen triangles (gl_VertexID based).
void drawFullscreenTriangle();

}  // namespace shadowlab
