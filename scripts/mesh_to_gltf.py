#!/usr/bin/env python3
"""Converts one public mesh to glTF 2.0 for the real-mesh test set (assets/models/README.md).

Standard library only, like scripts/make_gltf_model.py. scripts/fetch-meshes.sh fetches the packages
and calls this once per mesh; it is not meant to be edited by hand, and neither are its outputs.

What it keeps: every vertex and every triangle in the source's order, each wound as the source winds
it (polygons become fans from their first corner, which keeps their winding). Holes, non-manifold
edges, inconsistent winding and unused vertices are left as they are: the meshes are here for their
imperfections. What it changes: a rotation that makes the mesh's up axis +y (a proper rotation, so
the winding is kept), then one uniform scale and a translation so that the largest dimension of the
used vertices is SIZE world units (1.5 by default), their bounding box is centred on x = z = 0 and
its bottom lies on y = 0.

The file: POSITION float32, indices uint32, one triangle primitive (mode 4), no NORMAL (the
loader computes smooth normals), the buffer embedded as a base64 data URI, and asset.copyright and
asset.extras carrying the source, the licence and the counts measured below.

Formats: "off" (OFF, with optional colours after the face indices), "ply" (ASCII PLY, x y z and a
vertex_indices list), "js" (a CommonJS module with `exports.positions=[[x,y,z],...]` and
`exports.cells=[[a,b,c],...]`, as npm's bunny and teapot), "js-base64" (float32 positions and
uint32 cells in base64, as npm's snowden). A ".gz" source is read through gzip.

The counts (also printed, and checked by --expect): triangles; degenerate triangles (two corners on
one welded vertex); duplicate triangles (the corners of an earlier triangle, in either winding);
edges between welded vertices (vertices at identical positions are welded); boundary edges (one
face); non-manifold edges (three faces or more); inconsistent edges (two faces that traverse the
edge the same way: their windings disagree). Where there are duplicates, the last three again
with each duplicate left out, as the renderer's mesh topology counts them.

Usage: scripts/mesh_to_gltf.py SOURCE OUT.gltf --format FMT [--up=+y|-y|+z|-z|+x|-x] [--size 1.5]
           [--name NAME] [--source-text TEXT] [--license TEXT] [--expect triangles=N,boundary=N,...]
       scripts/mesh_to_gltf.py SOURCE --format FMT --check      (print the counts, write nothing)
Exit code 2 on a source it cannot read or counts that differ from --expect.
"""
import argparse
import base64
import gzip
import json
import os
import re
import struct
import sys


class InputError(Exception):
    pass


def open_text(path):
    return gzip.open(path, "rt", encoding="latin-1") if path.endswith(".gz") else open(path, encoding="latin-1")


def fan(polygon, where):
    if len(polygon) < 3:
        raise InputError("%s: a face with %d corners, expected at least 3" % (where, len(polygon)))
    return [(polygon[0], polygon[k], polygon[k + 1]) for k in range(1, len(polygon) - 1)]


def read_off(path):
    lines = []
    with open_text(path) as f:
        for line in f:
            words = line.split("#", 1)[0].split()
            if words:
                lines.append(words)
    if not lines or not lines[0][0].endswith("OFF"):
        raise InputError("%s: expected an OFF header" % path)
    header = lines[0][1:] if len(lines[0]) > 1 else lines[1]
    body = lines[1:] if len(lines[0]) > 1 else lines[2:]
    vertex_count, face_count = int(header[0]), int(header[1])
    if len(body) < vertex_count + face_count:
        raise InputError("%s: %d vertices and %d faces announced, %d lines follow"
                         % (path, vertex_count, face_count, len(body)))
    positions = [tuple(float(w) for w in body[i][:3]) for i in range(vertex_count)]
    triangles = []
    for words in body[vertex_count:vertex_count + face_count]:
        n = int(words[0])
        triangles += fan([int(w) for w in words[1:1 + n]], path)
    return positions, triangles


def read_ply(path):
    with open_text(path) as f:
        if f.readline().strip() != "ply":
            raise InputError("%s: expected a PLY header" % path)
        counts, properties, element = {}, {}, None
        while True:
            words = f.readline().split()
            if not words:
                raise InputError("%s: the header has no end_header" % path)
            if words[0] == "format" and words[1] != "ascii":
                raise InputError("%s: expected an ASCII PLY, got format %s" % (path, words[1]))
            if words[0] == "element":
                element = words[1]
                counts[element] = int(words[2])
                properties[element] = []
            elif words[0] == "property":
                properties[element].append(words[-1])
            elif words[0] == "end_header":
                break
        xyz = [properties["vertex"].index(k) for k in ("x", "y", "z")]
        positions = []
        for _ in range(counts["vertex"]):
            words = f.readline().split()
            positions.append(tuple(float(words[k]) for k in xyz))
        if properties["face"][0] not in ("vertex_indices", "vertex_index"):
            raise InputError("%s: expected the face's first property to be vertex_indices" % path)
        triangles = []
        for _ in range(counts["face"]):
            words = f.readline().split()
            n = int(words[0])
            triangles += fan([int(w) for w in words[1:1 + n]], path)
    return positions, triangles


def read_js(path):
    with open_text(path) as f:
        text = f.read()
    arrays = {}
    for key in ("positions", "cells"):
        match = re.search(r"exports\.%s\s*=\s*(\[\s*\[.*?\]\s*\])" % key, text, re.S)
        if not match:
            raise InputError("%s: no `exports.%s = [[...]]` array" % (path, key))
        arrays[key] = json.loads(match.group(1))
    triangles = []
    for cell in arrays["cells"]:
        triangles += fan(cell, path)
    return [tuple(float(c) for c in p) for p in arrays["positions"]], triangles


def read_js_base64(path):
    with open_text(path) as f:
        text = f.read()
    arrays = {}
    for kind, data in re.findall(r'exports\.\w+\s*=\s*require\("\./load"\)\((\w+),\s*"([^"]*)"\)', text):
        raw = base64.b64decode(data)
        code = {"Float32Array": "f", "Uint32Array": "I"}.get(kind)
        if code is None or len(raw) % 12:
            raise InputError("%s: expected Float32Array or Uint32Array triples, got %s" % (path, kind))
        arrays[kind] = struct.unpack("<%d%s" % (len(raw) // 4, code), raw)
    if set(arrays) != {"Float32Array", "Uint32Array"}:
        raise InputError("%s: expected base64 positions (Float32Array) and cells (Uint32Array)" % path)
    p, c = arrays["Float32Array"], arrays["Uint32Array"]
    return ([tuple(p[i:i + 3]) for i in range(0, len(p), 3)],
            [tuple(c[i:i + 3]) for i in range(0, len(c), 3)])


READERS = {"off": read_off, "ply": read_ply, "js": read_js, "js-base64": read_js_base64}


def measure(positions, triangles):
    """Counts of the mesh as it is (module docstring): welding only identical positions."""
    weld, welded = {}, []
    for p in positions:
        welded.append(weld.setdefault(p, len(weld)))
    def edge_counts(skip_duplicates):
        faces_on_edge = {}  # (smaller, larger) -> list of "runs smaller -> larger" per face
        seen = set()
        degenerate = duplicates = 0
        for t in triangles:
            a, b, c = (welded[i] for i in t)
            if a == b or b == c or c == a:
                degenerate += 1
                continue
            corners = frozenset((a, b, c))
            if corners in seen:
                duplicates += 1
                if skip_duplicates:
                    continue
            seen.add(corners)
            for u, v in ((a, b), (b, c), (c, a)):
                faces_on_edge.setdefault((u, v) if u < v else (v, u), []).append(u < v)
        boundary = nonmanifold = inconsistent = 0
        for runs in faces_on_edge.values():
            if len(runs) == 1:
                boundary += 1
            elif len(runs) > 2:
                nonmanifold += 1
            elif runs[0] == runs[1]:
                inconsistent += 1
        return degenerate, duplicates, len(faces_on_edge), boundary, nonmanifold, inconsistent

    degenerate, duplicates, edges, boundary, nonmanifold, inconsistent = edge_counts(False)
    counts = {"vertices": len(positions), "welded_vertices": len(weld),
              "unused_vertices": len(positions) - len(set(i for t in triangles for i in t)),
              "triangles": len(triangles), "degenerate_triangles": degenerate, "duplicate_triangles": duplicates,
              "edges": edges, "boundary_edges": boundary, "nonmanifold_edges": nonmanifold,
              "inconsistent_edges": inconsistent}
    if duplicates:
        # As buildTopology counts (mesh_topology.h): each duplicate left out, the first one kept.
        _, _, _, boundary, nonmanifold, inconsistent = edge_counts(True)
        counts.update(boundary_edges_without_duplicates=boundary, nonmanifold_edges_without_duplicates=nonmanifold,
                      inconsistent_edges_without_duplicates=inconsistent)
    return counts


# Proper rotations taking the named axis to +y (determinant +1: the winding is kept).
UP = {
    "+y": lambda x, y, z: (x, y, z),
    "-y": lambda x, y, z: (x, -y, -z),
    "+z": lambda x, y, z: (x, z, -y),
    "-z": lambda x, y, z: (x, -z, y),
    "+x": lambda x, y, z: (-y, x, z),
    "-x": lambda x, y, z: (y, -x, z),
}


def normalise(positions, triangles, up, size):
    rotate = UP[up]
    rotated = [rotate(*p) for p in positions]
    used = sorted(set(i for t in triangles for i in t))
    lo = [min(rotated[i][k] for i in used) for k in range(3)]
    hi = [max(rotated[i][k] for i in used) for k in range(3)]
    scale = size / max(hi[k] - lo[k] for k in range(3))
    offset = (-0.5 * (lo[0] + hi[0]), -lo[1], -0.5 * (lo[2] + hi[2]))
    return [tuple((p[k] + offset[k]) * scale for k in range(3)) for p in rotated]


def gltf(name, positions, triangles, copyright_text, extras):
    position_bytes = struct.pack("<%df" % (3 * len(positions)), *(c for p in positions for c in p))
    index_bytes = struct.pack("<%dI" % (3 * len(triangles)), *(i for t in triangles for i in t))
    blob = position_bytes + index_bytes
    # Accessor bounds from the float32 values the file holds (glTF requires them to be exact).
    stored = struct.unpack("<%df" % (3 * len(positions)), position_bytes)
    lo = [min(stored[k::3]) for k in range(3)]
    hi = [max(stored[k::3]) for k in range(3)]
    return {
        "asset": {"version": "2.0", "generator": "shadowlab scripts/mesh_to_gltf.py",
                  "copyright": copyright_text, "extras": extras},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": name, "mesh": 0}],
        "meshes": [{"name": name, "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode("ascii")}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(position_bytes), "target": 34962},
            {"buffer": 0, "byteOffset": len(position_bytes), "byteLength": len(index_bytes), "target": 34963},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5125, "count": 3 * len(triangles), "type": "SCALAR"},
        ],
    }


def parse_expect(text):
    expect = {}
    for item in filter(None, (text or "").split(",")):
        key, _, value = item.partition("=")
        expect[key.strip()] = int(value)
    return expect


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("source")
    parser.add_argument("out", nargs="?")
    parser.add_argument("--format", required=True, choices=sorted(READERS))
    parser.add_argument("--up", default="+y", choices=sorted(UP))
    parser.add_argument("--size", type=float, default=1.5)
    parser.add_argument("--name", default=None)
    parser.add_argument("--source-text", default="")
    parser.add_argument("--license", default="")
    parser.add_argument("--expect", default="", help="comma-separated key=count, keys as printed")
    parser.add_argument("--check", action="store_true", help="print the counts only")
    args = parser.parse_args()
    try:
        positions, triangles = READERS[args.format](args.source)
        if not triangles:
            raise InputError("%s: no triangles" % args.source)
        bad = [i for t in triangles for i in t if not 0 <= i < len(positions)]
        if bad:
            raise InputError("%s: index %d out of range (%d vertices)" % (args.source, bad[0], len(positions)))
        counts = measure(positions, triangles)
        print("%s: %s" % (args.name or os.path.basename(args.source),
                          ", ".join("%s %d" % (k.replace("_", " "), v) for k, v in counts.items())))
        differ = {k: (v, counts.get(k)) for k, v in parse_expect(args.expect).items() if counts.get(k) != v}
        if differ:
            raise InputError("%s: counts differ from the expected ones (assets/models/README.md): %s" % (
                args.source, ", ".join("%s: expected %d, got %s" % (k, e, g) for k, (e, g) in differ.items())))
        if args.check:
            return 0
        if not args.out:
            raise InputError("an output path is required unless --check")
        name = args.name or os.path.splitext(os.path.basename(args.out))[0]
        extras = dict(counts, source=args.source_text, license=args.license, up=args.up, size=args.size)
        document = gltf(name, normalise(positions, triangles, args.up, args.size), triangles,
                        args.license, extras)
    except (InputError, OSError, ValueError, IndexError, KeyError) as e:
        print("mesh_to_gltf: %s" % e, file=sys.stderr)
        return 2
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    tmp = args.out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(document, f, separators=(",", ":"))
        f.write("\n")
    os.replace(tmp, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
