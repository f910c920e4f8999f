#!/usr/bin/env python3
"""Regenerates techniques/core/gl/functions.inc: every OpenGL 1.0-4.5 core entry point of the
Khronos header glcorearb.h, as X(name, PFN type) lines for techniques/core/gl/loader.h.
Run once when the GL version changes; the output is committed."""
import re, sys
header = sys.argv[1] if len(sys.argv) > 1 else '/usr/include/GL/glcorearb.h'
out, section = [], None
for line in open(header):
    m = re.match(r'#ifndef (GL_\w+)$', line.strip())
    if m:
        section = m.group(1)
    m = re.match(r'GLAPI .*?APIENTRY (gl\w+) \(', line)
    if m and section and section.startswith('GL_VERSION_'):
        major, minor = map(int, section[len('GL_VERSION_'):].split('_'))
        if (major, minor) <= (4, 5):
            out.append(m.group(1))
with open('techniques/core/gl/functions.inc', 'w') as f:
    f.write('// Every OpenGL 1.0-4.5 core entry point, generated from Khronos glcorearb.h by\n'
            '// scripts/gen_gl_functions.py. X(name, PFN type) lines for gl/loader.h.\n')
    for n in out:
        f.write(f'X({n}, PFN{n.upper()}PROC)\n')
with open('techniques/core/gl/names.inc', 'w') as f:
    f.write('// glFoo -> sl_glFoo for every entry point of gl/functions.inc (generated with it).\n')
    for n in out:
        f.write(f'#define {n} sl_{n}\n')
