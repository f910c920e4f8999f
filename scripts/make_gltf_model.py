#!/usr/bin/env python3
"""Writes assets/models/torus.gltf: a low-poly torus (480 triangles) for the `contact` scene.

Standard library only. The torus lies in the xz plane (axis +y), centred at the origin, with major
radius 0.35 and tube radius 0.12, so it rests on a floor when translated up by 0.12. POSITION and
NORMAL are float32, indices uint16, and the buffer is embedded as a base64 data URI so the file
stands alone. Triangles are wound counter-clockwise seen from outside (checked below).

Usage: scripts/make_gltf_model.py [output path]   (default: assets/models/torus.gltf)
"""
import base64
import json
import math
import os
import struct
import sys

MAJOR_RADIUS = 0.35
TUBE_RADIUS = 0.12
MAJOR_SEGMENTS = 20  # around the y axis
TUBE_SEGMENTS = 12   # around the tube: 20 * 12 * 2 = 480 triangles. A multiple of 4, so that
                     # a vertex lies at the very bottom (y = -0.12) and the torus touches the floor.


def torus():
    positions, normals, indices = [], [], []
    for i in range(MAJOR_SEGMENTS):
        u = 2.0 * math.pi * i / MAJOR_SEGMENTS
        for j in range(TUBE_SEGMENTS):
            v = 2.0 * math.pi * j / TUBE_SEGMENTS
            n = (math.cos(v) * math.cos(u), math.sin(v), math.cos(v) * math.sin(u))
            ring = MAJOR_RADIUS + TUBE_RADIUS * math.cos(v)
            positions.append((ring * math.cos(u), TUBE_RADIUS * math.sin(v), ring * math.sin(u)))
            normals.append(n)

    def at(i, j):
        return (i % MAJOR_SEGMENTS) * TUBE_SEGMENTS + (j % TUBE_SEGMENTS)

    for i in range(MAJOR_SEGMENTS):
        for j in range(TUBE_SEGMENTS):
            a, b, c, d = at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)
            indices += [a, d, c, a, c, b]

    # Check the winding against the analytic normals: cross(b - a, c - a) . n > 0.
    for t in range(0, len(indices), 3):
        a, b, c = (positions[k] for k in indices[t:t + 3])
        e1 = [b[k] - a[k] for k in range(3)]
        e2 = [c[k] - a[k] for k in range(3)]
        cross = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                 e1[0] * e2[1] - e1[1] * e2[0])
        n = normals[indices[t]]
        assert sum(cross[k] * n[k] for k in range(3)) > 0.0, "triangle %d wound inwards" % (t // 3)
    return positions, normals, indices


def gltf(positions, normals, indices):
    position_bytes = b"".join(struct.pack("<3f", *p) for p in positions)
    normal_bytes = b"".join(struct.pack("<3f", *n) for n in normals)
    index_bytes = b"".join(struct.pack("<H", k) for k in indices)
    index_bytes += b"\0" * (-len(index_bytes) % 4)
    blob = position_bytes + normal_bytes + index_bytes
    lo = [min(p[k] for p in positions) for k in range(3)]
    hi = [max(p[k] for p in positions) for k in range(3)]
    return {
        "asset": {"version": "2.0", "generator": "shadowlab scripts/make_gltf_model.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "torus", "mesh": 0}],
        "meshes": [{"name": "torus", "primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "mode": 4}]}],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(blob).decode("ascii")}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(position_bytes), "target": 34962},
            {"buffer": 0, "byteOffset": len(position_bytes), "byteLength": len(normal_bytes),
             "target": 34962},
            {"buffer": 0, "byteOffset": len(position_bytes) + len(normal_bytes),
             "byteLength": 2 * len(indices), "target": 34963},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3",
             "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5126, "count": len(normals), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": len(indices), "type": "SCALAR"},
        ],
    }


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "assets", "models", "torus.gltf")
    positions, normals, indices = torus()
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(gltf(positions, normals, indices), f, indent=1)
        f.write("\n")
    os.replace(tmp, out)
    print("wrote %s (%d vertices, %d triangles)" % (out, len(positions), len(indices) // 3))


if __name__ == "__main__":
    main()
