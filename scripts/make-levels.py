#!/usr/bin/env python3
"""Writes the bundled level files under assets/levels/ (committed; rerun to regenerate):

  plate.obj              a steel plate: a closed box 1 cm thick (x), 2 m wide (y) and tall (z),
                         centred on the origin: 8 vertices, 12 triangles
  plate.gltf, plate.bin  the same box as glTF 2.0 with an external buffer (y-up, as glTF is)
  ramp.glb               a ramp as binary glTF: a slope of 3 in 4 (36.87 degrees, sine 0.6)
                         rising along +x from z = 0 at x = 0 to z = 6 at x = 8, 4 m wide, and a
                         flat 5 m top beyond it (every coordinate exact in f32)
  corner.obj             a concave corner: a floor falling from z = 0.6 at x = -2 to z = 0 at
                         x = 2 (y in [-2, 2]; 8.5 degrees, towards the wall) and a wall x = 2
                         up to z = 2, each two triangles
  berm.obj               an earth berm behind a firing range: a closed prism 24 m long (y), its
                         cross-section a trapezoid 6 m deep at the foot (x in [-3, 3]) and 1.5 m
                         at the top (x in [-0.75, 0.75]), 3 m high: slopes of 4 in 3 (53.13
                         degrees); 8 vertices, 12 triangles
  hill.png               a 65 x 65 16-bit grayscale heightfield: a Gaussian hill of 20000 units
                         at its centre, width (sigma) 10 samples

Standard library only (struct, zlib, json), so it runs anywhere Python 3 does.
"""
import json
import math
import os
import struct
import zlib

OUT = os.path.join(os.path.dirname(__file__), "..", "assets", "levels")


def box(hx, hy, hz):
    v = [(sx * hx, sy * hy, sz * hz) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    # vertex index = 4 * (x > 0) + 2 * (y > 0) + (z > 0); faces wound outwards
    quads = [
        (0, 1, 3, 2),  # -x
        (4, 6, 7, 5),  # +x
        (0, 4, 5, 1),  # -y
        (2, 3, 7, 6),  # +y
        (0, 2, 6, 4),  # -z
        (1, 5, 7, 3),  # +z
    ]
    t = []
    for a, b, c, d in quads:
        t += [(a, b, c), (a, c, d)]
    return v, t


def write_obj(path, v, t, comment):
    with open(path, "w") as f:
        f.write(f"# {comment}\n# Written by scripts/make-levels.py.\n")
        for p in v:
            f.write("v %r %r %r\n" % p)
        for a, b, c in t:
            f.write(f"f {a + 1} {b + 1} {c + 1}\n")


def gltf_parts(v, t):
    # Volley is z-up, glTF y-up: a Volley point (x, y, z) is the glTF point (x, z, -y).
    g = [(x, z, -y) for x, y, z in v]
    pos = b"".join(struct.pack("<3f", *p) for p in g)
    idx = b"".join(struct.pack("<3I", *tri) for tri in t)
    lo = [min(p[k] for p in g) for k in range(3)]
    hi = [max(p[k] for p in g) for k in range(3)]
    doc = {
        "asset": {"version": "2.0", "generator": "scripts/make-levels.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"byteLength": len(pos) + len(idx)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos), "target": 34962},
            {"buffer": 0, "byteOffset": len(pos), "byteLength": len(idx), "target": 34963},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(g), "type": "VEC3",
             "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5125, "count": 3 * len(t), "type": "SCALAR"},
        ],
    }
    return doc, pos + idx


def write_gltf(path, bin_name, v, t):
    doc, data = gltf_parts(v, t)
    doc["buffers"][0]["uri"] = bin_name
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    with open(os.path.join(os.path.dirname(path), bin_name), "wb") as f:
        f.write(data)


def write_glb(path, v, t):
    doc, data = gltf_parts(v, t)
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    data += b"\0" * (-len(data) % 4)
    total = 12 + 8 + len(js) + 8 + len(data)
    with open(path, "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, total))
        f.write(struct.pack("<I4s", len(js), b"JSON") + js)
        f.write(struct.pack("<I4s", len(data), b"BIN\0") + data)


def write_png16(path, w, h, value):
    raw = b""
    for r in range(h):
        j = h - 1 - r  # the top row is the grid's far edge (+y)
        raw += b"\0" + b"".join(struct.pack(">H", value(i, j)) for i in range(w))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 16, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


def main():
    os.makedirs(OUT, exist_ok=True)
    v, t = box(0.005, 1.0, 1.0)
    write_obj(os.path.join(OUT, "plate.obj"), v, t,
              "A steel plate: a closed box 1 cm thick (x), 2 m wide (y) and tall (z).")
    write_gltf(os.path.join(OUT, "plate.gltf"), "plate.bin", v, t)
    # The ramp: rises 6 m over x in [0, 8], then flat for 5 m; y in [-2, 2].
    top = (8, 6)
    rv = [(0, -2, 0), (0, 2, 0), (top[0], 2, top[1]), (top[0], -2, top[1]),
          (top[0] + 5, 2, top[1]), (top[0] + 5, -2, top[1])]
    rt = [(0, 3, 2), (0, 2, 1), (3, 5, 4), (3, 4, 2)]
    write_glb(os.path.join(OUT, "ramp.glb"), rv, rt)
    cv = [(-2, -2, 0.6), (2, -2, 0), (2, 2, 0), (-2, 2, 0.6), (2, -2, 2), (2, 2, 2)]
    ct = [(0, 1, 2), (0, 2, 3), (1, 4, 5), (1, 5, 2)]
    write_obj(os.path.join(OUT, "corner.obj"), cv, ct,
              "A concave corner: a floor falling 0.6 m towards the wall x = 2, 2 m high.")
    bv = [(sx * foot, y, 0) for y in (-12, 12) for sx, foot in ((-1, 3), (1, 3))] + \
         [(sx * 0.75, y, 3) for y in (-12, 12) for sx in (-1, 1)]
    # 0 (-3,-12,0) 1 (3,-12,0) 2 (-3,12,0) 3 (3,12,0) 4 (-.75,-12,3) 5 (.75,-12,3)
    # 6 (-.75,12,3) 7 (.75,12,3); faces wound outwards
    bq = [(0, 4, 6, 2),  # front slope (-x)
          (1, 3, 7, 5),  # back slope (+x)
          (4, 5, 7, 6),  # top
          (0, 2, 3, 1),  # foot (-z)
          (0, 1, 5, 4),  # end at y = -12
          (2, 6, 7, 3)]  # end at y = +12
    bt = []
    for a, b, c, d in bq:
        bt += [(a, b, c), (a, c, d)]
    write_obj(os.path.join(OUT, "berm.obj"), bv, bt,
              "An earth berm: a prism 24 m long (y), 6 m deep at its foot, 1.5 m at its 3 m top.")
    write_png16(os.path.join(OUT, "hill.png"), 65, 65,
                lambda i, j: round(20000 * math.exp(-((i - 32) ** 2 + (j - 32) ** 2) / 200.0)))


if __name__ == "__main__":
    main()
