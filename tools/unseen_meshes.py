#!/usr/bin/env python3
"""unseen_meshes.py GEOSEP OUTDIR - write the "unseen" test meshes of
doc/accuracy.md ("Meshes nobody tuned for") into OUTDIR as OBJ files.

The ones `geosep generate` and `geosep subdivide` make are made by GEOSEP
(the geosep command); the others here, deterministically (Python's random
with fixed seeds): a cone with a sharp apex, a jittered annulus (a disc with
a hole), a bumpy and a spiky sphere (radial displacement of sphere:4 or 5),
height fields on anisotropic, jittered (sliver) and graded grids, a graded
polar disc, four components of very different sizes, and two rescaled
copies (1e-3, 1e4). Standard library only. tools/unseen.sh uses it."""
import math
import os
import random
import subprocess
import sys


def write(fn, V, F):
    with open(fn, "w") as f:
        for v in V:
            f.write("v %.17g %.17g %.17g\n" % tuple(v))
        for t in F:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


def read(fn):
    V, F = [], []
    for line in open(fn):
        s = line.split()
        if not s:
            continue
        if s[0] == "v":
            V.append([float(x) for x in s[1:4]])
        elif s[0] == "f":
            F.append([int(x.split("/")[0]) - 1 for x in s[1:4]])
    return V, F


def cone(nu, nv, R, H):
    """A cone of height H, base radius R, apex a vertex (a sharp tip), open base."""
    V, F = [[0, 0, H]], []
    for j in range(1, nv + 1):
        t = j / nv
        for i in range(nu):
            u = 2 * math.pi * i / nu
            V.append([R * t * math.cos(u), R * t * math.sin(u), H * (1 - t)])
    for i in range(nu):
        F.append([0, 1 + i, 1 + (i + 1) % nu])
    for j in range(1, nv):
        b0, b1 = 1 + (j - 1) * nu, 1 + j * nu
        for i in range(nu):
            i1 = (i + 1) % nu
            F.append([b0 + i, b1 + i, b1 + i1])
            F.append([b0 + i, b1 + i1, b0 + i1])
    return V, F


def annulus(nu, nr, r0, r1, seed=3):
    """A flat ring r0 <= r <= r1, staggered rings, inner vertices jittered."""
    random.seed(seed)
    V, F = [], []
    for j in range(nr):
        r = r0 + (r1 - r0) * j / (nr - 1)
        for i in range(nu):
            u = 2 * math.pi * (i + 0.5 * (j % 2)) / nu
            jr = 0 if j in (0, nr - 1) else (r1 - r0) / (nr - 1) * 0.25 * (random.random() - 0.5)
            ju = 0.25 * (random.random() - 0.5) * 2 * math.pi / nu
            V.append([(r + jr) * math.cos(u + ju), (r + jr) * math.sin(u + ju), 0.0])
    return V, ring_faces(nu, nr)


def ring_faces(nu, nr):
    F = []
    for j in range(nr - 1):
        for i in range(nu):
            a, b = j * nu + i, j * nu + (i + 1) % nu
            c, d = (j + 1) * nu + i, (j + 1) * nu + (i + 1) % nu
            if j % 2 == 0:
                F += [[a, b, c], [b, d, c]]
            else:
                F += [[a, b, d], [a, d, c]]
    return F


def displaced(fn, amp, freq=None, seed=5):
    """Vertices of fn scaled radially: by 1 + amp sin(fx) sin(fy) sin(fz)
    plus 0.3 amp of noise (freq), or by 1 + amp of noise."""
    V, F = read(fn)
    random.seed(seed)
    for v in V:
        if freq:
            s = 1 + amp * math.sin(freq * v[0]) * math.sin(freq * v[1]) * math.sin(freq * v[2]) \
                + amp * 0.3 * (random.random() - 0.5)
        else:
            s = 1 + amp * (random.random() - 0.5)
        for k in range(3):
            v[k] *= s
    return V, F


def grid(nx, ny, fx, fy, fz, diag=lambda i, j: True):
    V, F = [], []
    for j in range(ny):
        for i in range(nx):
            x, y = fx(i, j), fy(i, j)
            V.append([x, y, fz(x, y)])
    for j in range(ny - 1):
        for i in range(nx - 1):
            a = j * nx + i
            if diag(i, j):
                F += [[a, a + 1, a + 1 + nx], [a, a + 1 + nx, a + nx]]
            else:
                F += [[a, a + 1, a + nx], [a + 1, a + 1 + nx, a + nx]]
    return V, F


def aniso(nx, ny, W, H, amp):
    """Height field amp sin 3x cos 2y on a W x H grid of nx x ny vertices."""
    return grid(nx, ny, lambda i, j: W * i / (nx - 1), lambda i, j: H * j / (ny - 1),
                lambda x, y: amp * math.sin(3 * x) * math.cos(2 * y))


def jitter(n, amp, seed=9):
    """Height field on [0,1]^2, inner vertices moved by up to amp/2 cells,
    diagonals at random: slivers (min angle ~0.5 deg)."""
    random.seed(seed)
    V, F = [], []
    for j in range(n):
        for i in range(n):
            x, y = i / (n - 1), j / (n - 1)
            if 0 < i < n - 1:
                x += amp * (random.random() - 0.5) / (n - 1)
            if 0 < j < n - 1:
                y += amp * (random.random() - 0.5) / (n - 1)
            V.append([x, y, 0.3 * math.sin(4 * x) * math.sin(3 * y)])
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            if random.random() < 0.5:
                F += [[a, a + 1, a + 1 + n], [a, a + 1 + n, a + n]]
            else:
                F += [[a, a + 1, a + n], [a + 1, a + 1 + n, a + n]]
    return V, F


def terrain(n, amp, seed=11):
    """Height field 0.2 sin 6x cos 5y on an n x n grid of [0,1]^2, each
    height moved by up to +-amp/2 grid cells (uniform noise): a rough
    surface."""
    random.seed(seed)
    return grid(n, n, lambda i, j: i / (n - 1), lambda i, j: j / (n - 1),
                lambda x, y: 0.2 * math.sin(6 * x) * math.cos(5 * y) + amp * (random.random() - 0.5) / (n - 1))


def graded(n, p):
    """Height field on the grid x = (i/(n-1))^p, y = (j/(n-1))^p: cells from
    tiny (at the origin) to large."""
    return grid(n, n, lambda i, j: (i / (n - 1)) ** p, lambda i, j: (j / (n - 1)) ** p,
                lambda x, y: 0.25 * math.sin(5 * x) * math.sin(5 * y))


def polar(nu, nr, r0):
    """A wavy disc with a hole of radius r0: rings spaced geometrically
    from r0 to 1 (edges from ~r0 to ~0.17)."""
    V, q = [], (1 / r0) ** (1 / (nr - 1))
    for j in range(nr):
        r = r0 * q ** j
        for i in range(nu):
            u = 2 * math.pi * (i + 0.5 * (j % 2)) / nu
            V.append([r * math.cos(u), r * math.sin(u),
                      0.3 * math.sin(3 * r * math.cos(u)) * math.cos(2 * r * math.sin(u))])
    return V, ring_faces(nu, nr)


def multi(fa, fb):
    """Four components: fa, fb moved by (3,0,0), a tetrahedron, a triangle."""
    V, F = read(fa)

    def add(V2, F2, off):
        b = len(V)
        V.extend([[v[0] + off[0], v[1] + off[1], v[2] + off[2]] for v in V2])
        F.extend([[t[0] + b, t[1] + b, t[2] + b] for t in F2])

    add(*read(fb), (3, 0, 0))
    add([[0, 0, 0], [0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]], [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], (0, 3, 0))
    add([[0, 0, 0], [0.05, 0, 0], [0, 0.05, 0]], [[0, 1, 2]], (0, -3, 0))
    return V, F


def scaled(fn, s):
    V, F = read(fn)
    return [[x * s for x in v] for v in V], F


GENERATED = {  # name: geosep generate spec
    "knot-thin": "knot:200,10,0.15", "knot-hex": "knot:300,6,0.1", "knot-fat": "knot:60,24,0.5",
    "cyl-thin": "cylinder:20,150,0.1,6", "cyl-needle": "cylinder:12,100,0.05,10",
    "cyl-hex": "cylinder:6,300,0.05,10", "cube16": "cube:16", "cube4": "cube:4",
    "torus-coarse": "torus:24,12,1,0.35", "torus-thin": "torus:120,8,1,0.1", "two": "two:30",
    "strip": "grid:400,3,10,0.05", "peaks6": "peaks:50",
    "sphere3": "sphere:3", "sphere4": "sphere:4", "sphere5": "sphere:5", "torus40": "torus:40,16,1,0.3",
}


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: unseen_meshes.py GEOSEP OUTDIR")
    g, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    p = lambda name: os.path.join(out, name + ".obj")
    for name, spec in GENERATED.items():
        subprocess.run([g, "generate", spec, "-o", p(name)], check=True, stdout=subprocess.DEVNULL)
    write(p("cone-sharp"), *cone(48, 40, 1, 3))
    write(p("cone-needle"), *cone(32, 60, 0.3, 5))
    write(p("annulus"), *annulus(80, 25, 0.3, 1))
    write(p("sphere-bumpy"), *displaced(p("sphere4"), 0.15, 7))
    write(p("sphere5-bumpy"), *displaced(p("sphere5"), 0.1, 11))
    write(p("sphere-spiky"), *displaced(p("sphere4"), 0.06))
    write(p("sphere-spiky2"), *displaced(p("sphere4"), 0.12))
    write(p("sphere5-spiky"), *displaced(p("sphere5"), 0.04))
    write(p("terrain"), *terrain(50, 1.5))
    write(p("aniso"), *aniso(20, 150, 2, 2, 0.4))
    write(p("aniso40"), *aniso(10, 300, 2, 2, 0.4))
    write(p("jitter"), *jitter(50, 0.9))
    write(p("graded"), *graded(50, 2.5))
    write(p("graded5"), *graded(45, 5.0))
    write(p("polar"), *polar(64, 40, 0.005))
    write(p("multi"), *multi(p("sphere3"), p("torus40")))
    write(p("cube-1e-3"), *scaled(p("cube16"), 1e-3))
    write(p("bumpy-1e4"), *scaled(p("sphere-bumpy"), 1e4))
    shared = os.environ.get("GEOSEP_SHARED", "")
    for name in ("homer", "rocker-arm"):
        src = os.path.join(shared, "meshes", name + ".obj")
        if shared and os.path.exists(src):
            subprocess.run([g, "subdivide", src, "-o", p(name + "-sub1")], check=True, stdout=subprocess.DEVNULL)


if __name__ == "__main__":
    main()
