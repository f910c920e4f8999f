// The GL helpers in one include: formats and memory counters (gl_format.h), buffers and vertex
// arrays (gl_buffer.h), textures, framebuffers and read-back (gl_texture.h), shader programs,
// compute and the program cache (gl_program.h), per-pass pipeline state (gl_state.h).
#pragma once
#include "gl/buffer.h"
#include "gl/format.h"
#include "gl/program.h"
#include "gl/state.h"
#include "gl/texture.h"

namespace shadowlab {

// One empty VAO for full-screen triangles (gl_VertexID based).
void drawFullscreenTriangle();

}  // namespace shadowlab
