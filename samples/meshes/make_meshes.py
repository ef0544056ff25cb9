#!/usr/bin/env python3
"""Writes the sample furniture meshes of samples/meshes/ (Python 3 stdlib only).

    python3 samples/meshes/make_meshes.py [OUTPUT_DIR]

Every piece is in metres, z up, with its origin at the centre of its
footprint on the floor.  Each file holds triangles only, wound
counter-clockwise seen from outside, with no degenerate triangle, so the
triangle count printed here is the count a loader must find:

    bed.obj     a double bed (boxes), no normals: flat shading
    lamp.obj    a bedside lamp: base, stem, bulb and shade, with vertex normals
                (smooth on the round sides, flat on the caps and rims)
    table.ply   a writing desk, ASCII PLY, no normals
    chair.gltf  a chair, glTF 2.0 with an embedded base64 buffer and flat
                normals; stored z up like the others (glTF's own convention
                is y up, so a glTF viewer shows it lying on its back)

The output is deterministic: running the script again rewrites the same bytes.
"""
import base64
import json
import math
import os
import struct
import sys


def box(x0, y0, z0, x1, y1, z1):
    """Six faces as 12 triangles, each corner (position, face normal)."""
    assert x0 < x1 and y0 < y1 and z0 < z1
    dx, dy, dz = x1 - x0, y1 - y0, z1 - z0
    # (corner, edge u, edge v) with u x v along the outward normal.
    faces = [
        ((x1, y0, z0), (0, dy, 0), (0, 0, dz), (1, 0, 0)),
        ((x0, y0, z0), (0, 0, dz), (0, dy, 0), (-1, 0, 0)),
        ((x0, y1, z0), (0, 0, dz), (dx, 0, 0), (0, 1, 0)),
        ((x0, y0, z0), (dx, 0, 0), (0, 0, dz), (0, -1, 0)),
        ((x0, y0, z1), (dx, 0, 0), (0, dy, 0), (0, 0, 1)),
        ((x0, y0, z0), (0, dy, 0), (dx, 0, 0), (0, 0, -1)),
    ]
    tris = []
    for p, u, v, n in faces:
        a = p
        b = tuple(p[i] + u[i] for i in range(3))
        c = tuple(p[i] + u[i] + v[i] for i in range(3))
        d = tuple(p[i] + v[i] for i in range(3))
        tris.append(((a, n), (b, n), (c, n)))
        tris.append(((a, n), (c, n), (d, n)))
    return tris


def ring(r, z, k, n):
    t = 2.0 * math.pi * (k % n) / n
    return (r * math.cos(t), r * math.sin(t), z)


def frustum_side(r0, z0, r1, z1, n, inward=False):
    """The side of a truncated cone, smooth normals (outward or inward)."""
    slope = (r0 - r1) / (z1 - z0)
    tris = []
    for k in range(n):
        corners = []
        for kk, r, z in ((k, r0, z0), (k + 1, r0, z0), (k + 1, r1, z1), (k, r1, z1)):
            t = 2.0 * math.pi * (kk % n) / n
            nx, ny, nz = math.cos(t), math.sin(t), slope
            s = math.sqrt(nx * nx + ny * ny + nz * nz)
            nrm = (nx / s, ny / s, nz / s)
            if inward:
                nrm = (-nrm[0], -nrm[1], -nrm[2])
            corners.append((ring(r, z, kk, n), nrm))
        a, b, c, d = corners
        if inward:
            tris.append((a, c, b))
            tris.append((a, d, c))
        else:
            tris.append((a, b, c))
            tris.append((a, c, d))
    return tris


def disc(r, z, n, up):
    """A flat cap as a fan around its centre, facing +z (up) or -z."""
    nrm = (0.0, 0.0, 1.0 if up else -1.0)
    c = ((0.0, 0.0, z), nrm)
    tris = []
    for k in range(n):
        p, q = (ring(r, z, k, n), nrm), (ring(r, z, k + 1, n), nrm)
        tris.append((c, p, q) if up else (c, q, p))
    return tris


def annulus(ri, ro, z, n, up):
    """A flat ring between radii ri < ro, facing +z (up) or -z."""
    nrm = (0.0, 0.0, 1.0 if up else -1.0)
    tris = []
    for k in range(n):
        i0, i1 = (ring(ri, z, k, n), nrm), (ring(ri, z, k + 1, n), nrm)
        o0, o1 = (ring(ro, z, k, n), nrm), (ring(ro, z, k + 1, n), nrm)
        if up:
            tris += [(i0, o0, o1), (i0, o1, i1)]
        else:
            tris += [(i0, o1, o0), (i0, i1, o1)]
    return tris


def uv_sphere(cx, cy, cz, r, n, m):
    """A sphere of n segments and m rings, smooth normals."""
    def corner(j, k):
        ph, t = math.pi * j / m, 2.0 * math.pi * (k % n) / n
        nrm = (math.sin(ph) * math.cos(t), math.sin(ph) * math.sin(t), math.cos(ph))
        if j == 0 or j == m:
            nrm = (0.0, 0.0, nrm[2])
        return ((cx + r * nrm[0], cy + r * nrm[1], cz + r * nrm[2]), nrm)
    tris = []
    for k in range(n):
        tris.append((corner(0, 0), corner(1, k), corner(1, k + 1)))
        tris.append((corner(m, 0), corner(m - 1, k + 1), corner(m - 1, k)))
        for j in range(1, m - 1):
            up0, up1 = corner(j, k), corner(j, k + 1)
            lo0, lo1 = corner(j + 1, k), corner(j + 1, k + 1)
            tris += [(lo0, lo1, up1), (lo0, up1, up0)]
    return tris


def bed():
    """A double bed, 1.6 m x 2.06 m, headboard at +y."""
    t = []
    for x in (-0.77, 0.71):
        for y in (-1.03, 0.91):
            t += box(x, y, 0.0, x + 0.06, y + 0.06, 0.12)      # legs
    t += box(-0.80, -1.03, 0.12, 0.80, 0.97, 0.30)             # frame
    t += box(-0.78, -1.01, 0.30, 0.78, 0.95, 0.52)             # mattress
    t += box(-0.80, 0.97, 0.00, 0.80, 1.03, 1.10)              # headboard
    t += box(-0.70, 0.52, 0.52, -0.08, 0.90, 0.64)             # pillows
    t += box(0.08, 0.52, 0.52, 0.70, 0.90, 0.64)
    t += box(-0.80, -1.03, 0.52, 0.80, 0.42, 0.56)             # duvet
    return t


def lamp():
    """A bedside lamp, 0.48 m tall: base, stem, bulb and a cone-shaped shade."""
    n = 32
    t = []
    t += frustum_side(0.08, 0.0, 0.08, 0.025, n)               # base
    t += disc(0.08, 0.025, n, True)
    t += disc(0.08, 0.0, n, False)
    m = 16
    t += frustum_side(0.008, 0.025, 0.008, 0.33, m)            # stem
    t += disc(0.008, 0.33, m, True)
    t += uv_sphere(0.0, 0.0, 0.36, 0.03, 12, 8)                 # bulb
    w = 0.003                                                  # shade wall
    t += frustum_side(0.16, 0.28, 0.10, 0.48, n)
    t += frustum_side(0.16 - w, 0.28, 0.10 - w, 0.48, n, inward=True)
    t += annulus(0.10 - w, 0.10, 0.48, n, True)
    t += annulus(0.16 - w, 0.16, 0.28, n, False)
    return t


def table():
    """A writing desk, 1.2 m x 0.6 m, 0.75 m high."""
    t = box(-0.60, -0.30, 0.72, 0.60, 0.30, 0.75)              # top
    for x in (-0.57, 0.53):
        for y in (-0.27, 0.23):
            t += box(x, y, 0.0, x + 0.04, y + 0.04, 0.72)      # legs
    t += box(-0.53, -0.27, 0.62, 0.53, -0.25, 0.72)            # aprons
    t += box(-0.53, 0.25, 0.62, 0.53, 0.27, 0.72)
    t += box(-0.57, -0.23, 0.62, -0.55, 0.23, 0.72)
    t += box(0.55, -0.23, 0.62, 0.57, 0.23, 0.72)
    return t


def chair():
    """A side chair: seat 0.45 m high, back at +y up to 0.90 m."""
    t = box(-0.225, -0.225, 0.43, 0.225, 0.225, 0.47)          # seat
    for x in (-0.215, 0.18):
        for y in (-0.215, 0.18):
            t += box(x, y, 0.0, x + 0.035, y + 0.035, 0.43)    # legs
    for x in (-0.215, 0.18):
        t += box(x, 0.18, 0.47, x + 0.035, 0.215, 0.90)        # back posts
    t += box(-0.18, 0.19, 0.62, 0.18, 0.21, 0.88)              # back panel
    t += box(-0.18, -0.205, 0.12, 0.18, -0.19, 0.15)           # front rail
    return t


def check(tris):
    for tri in tris:
        a, b, c = (corner[0] for corner in tri)
        e1 = [b[i] - a[i] for i in range(3)]
        e2 = [c[i] - a[i] for i in range(3)]
        cx = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
              e1[0] * e2[1] - e1[1] * e2[0])
        assert math.sqrt(sum(v * v for v in cx)) > 1e-9, "degenerate triangle"


def fmt(v):
    s = "%.6f" % v
    return "0.000000" if s == "-0.000000" else s


def indexed(tris, with_normals):
    """Shared vertices (position, or position + normal) and index triples."""
    index, verts, faces = {}, [], []
    for tri in tris:
        face = []
        for pos, nrm in tri:
            key = tuple(fmt(v) for v in pos)
            if with_normals:
                key += tuple(fmt(v) for v in nrm)
            if key not in index:
                index[key] = len(verts)
                verts.append((pos, nrm))
            face.append(index[key])
        faces.append(face)
    return verts, faces


def write_obj(path, title, tris, with_normals):
    verts, faces = indexed(tris, with_normals)
    with open(path, "w", newline="\n") as f:
        f.write("# %s: written by make_meshes.py; metres, z up, %d triangles\n"
                % (title, len(faces)))
        f.write("o %s\n" % title)
        for pos, _ in verts:
            f.write("v %s %s %s\n" % tuple(fmt(v) for v in pos))
        if with_normals:
            for _, nrm in verts:
                f.write("vn %s %s %s\n" % tuple(fmt(v) for v in nrm))
            for a, b, c in faces:
                f.write("f %d//%d %d//%d %d//%d\n" % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1))
        else:
            for a, b, c in faces:
                f.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))
    return len(faces)


def write_ply(path, title, tris):
    verts, faces = indexed(tris, False)
    with open(path, "w", newline="\n") as f:
        f.write("ply\nformat ascii 1.0\n")
        f.write("comment %s: written by make_meshes.py; metres, z up\n" % title)
        f.write("element vertex %d\n" % len(verts))
        f.write("property float x\nproperty float y\nproperty float z\n")
        f.write("element face %d\n" % len(faces))
        f.write("property list uchar int vertex_indices\nend_header\n")
        for pos, _ in verts:
            f.write("%s %s %s\n" % tuple(fmt(v) for v in pos))
        for a, b, c in faces:
            f.write("3 %d %d %d\n" % (a, b, c))
    return len(faces)


def write_gltf(path, title, tris):
    verts, faces = indexed(tris, True)
    assert len(verts) < 65536
    pos = [[float(fmt(v)) for v in p] for p, _ in verts]
    nrm = [[float(fmt(v)) for v in n] for _, n in verts]
    blob_pos = b"".join(struct.pack("<3f", *p) for p in pos)
    blob_nrm = b"".join(struct.pack("<3f", *n) for n in nrm)
    blob_idx = b"".join(struct.pack("<3H", *face) for face in faces)
    blob = blob_pos + blob_nrm + blob_idx
    while len(blob) % 4:
        blob += b"\0"
    lo = [min(p[i] for p in pos) for i in range(3)]
    hi = [max(p[i] for p in pos) for i in range(3)]
    doc = {
        "asset": {"version": "2.0", "generator": "Virtuelium-C make_meshes.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": title}],
        "meshes": [{"name": title, "primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
            "material": 0, "mode": 4}]}],
        "materials": [{"name": "wood", "pbrMetallicRoughness": {
            "baseColorFactor": [0.45, 0.30, 0.18, 1.0],
            "metallicFactor": 0.0, "roughnessFactor": 0.6}}],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64,"
                            + base64.b64encode(blob).decode("ascii")}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(blob_pos), "target": 34962},
            {"buffer": 0, "byteOffset": len(blob_pos), "byteLength": len(blob_nrm),
             "target": 34962},
            {"buffer": 0, "byteOffset": len(blob_pos) + len(blob_nrm),
             "byteLength": len(blob_idx), "target": 34963}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3",
             "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5126, "count": len(nrm), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": 3 * len(faces),
             "type": "SCALAR"}],
    }
    with open(path, "w", newline="\n") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    return len(faces)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    pieces = [("bed.obj", "bed", bed(), lambda p, n, t: write_obj(p, n, t, False)),
              ("lamp.obj", "lamp", lamp(), lambda p, n, t: write_obj(p, n, t, True)),
              ("table.ply", "table", table(), write_ply),
              ("chair.gltf", "chair", chair(), write_gltf)]
    for filename, title, tris, writer in pieces:
        check(tris)
        count = writer(os.path.join(out, filename), title, tris)
        print("%-11s %4d triangles" % (filename, count))


if __name__ == "__main__":
    main()
