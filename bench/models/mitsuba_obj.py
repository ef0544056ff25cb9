#!/usr/bin/env python3
"""Merges a Mitsuba 0.5 scene's OBJ shapes into one OBJ + MTL that vr-render
reads from one mesh line (bench/bench_textures.sh): the public textured
interiors of Benedikt Bitterli's rendering resources come as a scene.xml
with hundreds of OBJ files and no .mtl.

Each <shape type="obj"> becomes a group with `usemtl BSDF-ID`, its
vertices and normals moved by its toWorld matrix; each BSDF id becomes an
MTL material with the diffuse part the renderer can read: `Kd` from a
diffuse / roughplastic reflectance (rgb), `map_Kd` from its bitmap texture,
a grey Kd 0.578596 for conductors and glass (map them in the scene with
material.ID=db:...).  Other shapes (rectangles, spheres) and emitters are
left out: the benchmark scene adds its own lights.

Usage: mitsuba_obj.py SCENE.xml OUT.obj   (OUT.mtl is written beside; the
texture paths stay relative to the scene's folder, so OUT goes there).
"""
import os
import sys
import xml.etree.ElementTree as ET


def bsdf_colour(b):
    """(rgb, texture) of a BSDF element's diffuse part."""
    inner = b
    while inner.get("type") == "twosided":
        nxt = inner.find("bsdf")
        if nxt is None:
            break
        inner = nxt
    for child in inner:
        name = child.get("name")
        if name in ("reflectance", "diffuseReflectance"):
            if child.tag == "rgb":
                return [float(x) for x in child.get("value").replace(",", " ").split()], None
            if child.tag == "texture":
                for s in child.findall("string"):
                    if s.get("name") == "filename":
                        return None, s.get("value")
    return [0.578596] * 3, None


def matrix(shape):
    t = shape.find("transform")
    if t is None or t.find("matrix") is None:
        return None
    v = [float(x) for x in t.find("matrix").get("value").split()]
    return [v[0:4], v[4:8], v[8:12]]


def main():
    scene, out = sys.argv[1], sys.argv[2]
    root = ET.parse(scene).getroot()
    base = os.path.dirname(os.path.abspath(scene))
    bsdfs = {}
    for b in root.findall("bsdf"):
        if b.get("id"):
            bsdfs[b.get("id")] = bsdf_colour(b)
    mtl = os.path.splitext(out)[0] + ".mtl"
    used = set()
    nv = nt = nn = 0
    tris = 0
    with open(out, "w") as o:
        o.write("# merged from %s by bench/models/mitsuba_obj.py\n" % os.path.basename(scene))
        o.write("mtllib %s\n" % os.path.basename(mtl))
        for k, shape in enumerate(root.findall("shape")):
            if shape.get("type") != "obj":
                continue
            fn = [s.get("value") for s in shape.findall("string") if s.get("name") == "filename"][0]
            ref = shape.find("ref")
            mat = ref.get("id") if ref is not None else "default"
            used.add(mat)
            m = matrix(shape)
            v, vt, vn, faces = [], [], [], []
            with open(os.path.join(base, fn)) as f:
                for line in f:
                    p = line.split()
                    if not p:
                        continue
                    if p[0] == "v":
                        x = [float(c) for c in p[1:4]]
                        if m:
                            x = [m[r][0] * x[0] + m[r][1] * x[1] + m[r][2] * x[2] + m[r][3] for r in range(3)]
                        v.append(x)
                    elif p[0] == "vt":
                        vt.append(p[1:3])
                    elif p[0] == "vn":
                        x = [float(c) for c in p[1:4]]
                        if m:
                            x = [m[r][0] * x[0] + m[r][1] * x[1] + m[r][2] * x[2] for r in range(3)]
                        vn.append(x)
                    elif p[0] == "f":
                        faces.append(p[1:])
            o.write("g shape%d\nusemtl %s\n" % (k, mat))
            for x in v:
                o.write("v %.7g %.7g %.7g\n" % tuple(x))
            for x in vt:
                o.write("vt %s %s\n" % tuple(x))
            for x in vn:
                o.write("vn %.7g %.7g %.7g\n" % tuple(x))
            for fc in faces:
                refs = []
                for c in fc:
                    idx = c.split("/")
                    out_idx = []
                    for j, off in enumerate((nv, nt, nn)):
                        if j < len(idx) and idx[j]:
                            i = int(idx[j])
                            i = i + off if i > 0 else i
                            out_idx.append(str(i))
                        else:
                            out_idx.append("")
                    while out_idx and out_idx[-1] == "":
                        out_idx.pop()
                    refs.append("/".join(out_idx))
                o.write("f %s\n" % " ".join(refs))
                tris += len(fc) - 2
            nv += len(v)
            nt += len(vt)
            nn += len(vn)
    with open(mtl, "w") as o:
        for mat in sorted(used):
            rgb, tex = bsdfs.get(mat, ([0.578596] * 3, None))
            o.write("newmtl %s\n" % mat)
            o.write("Kd %.6g %.6g %.6g\n" % tuple(rgb if rgb else (1, 1, 1)))
            if tex:
                o.write("map_Kd %s\n" % tex)
            o.write("\n")
    print("%s: %d vertices, %d triangles, %d materials" % (out, nv, tris, len(used)))


if __name__ == "__main__":
    main()
