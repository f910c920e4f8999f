// OpenGL 4.5 core entry points, loaded at run time through the current context's
// GetProcAddress (EGL, OSMesa or GLFW). No GL library is linked, so one binary can use any of the
// three context kinds (only one per process: OSMesa does not mix with libEGL/libGL).
// Code calls glFoo(...) as usual: each name is a macro for the loaded pointer sl_glFoo.
#pragma once
#include <GL/glcorearb.h>

#define X(name, type) extern type sl_##name;
#include "gl/functions.inc"
#undef X

namespace shadowlab {
using GLProcLoader = void* (*)(const char* name);
// Loads every entry point; returns the names of the OpenGL 4.5 functions that are missing.
int loadGLFunctions(GLProcLoader loader);
}  // namespace shadowlab

#include "gl/names.inc"
