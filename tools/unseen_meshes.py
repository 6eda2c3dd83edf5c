#!/usr/bin/env python3
"""unseen_meshes.py GEOSEP OUTDIR - write the "unseen" test meshes of
doc/accuracy.md ("Meshes nobody tuned for") into OUTDIR as OBJ files.

The ones `geosep generate` and `geosep subdivide` make are made by GEOSEP
(the geosep command); the others here, deterministically (Python's random
with fixed seeds): a cone with a sharp apex, a jittered annulus (a disc with
a hole), a bumpy and a spiky sphere (radial displacement of sphere:4 or 5),
height fields on anisotropic, jittered (sliver) and graded grids, a graded
polar disc, four components of very different sizes, two rescaled
copies (1e-3, 1e4), and closed plates with square holes through them
(genus 2; their holes' corners are sharp saddles). Standard library only.
tools/unseen.sh uses it. More kinds, not in its default list, for hunting:
flat domains with reflex corners and holes (masked grids: comb, L, spiral,
perforated), slabs of any genus, surfaces of revolution (a dumbbell),
a helix ribbon, the monkey saddle, a random Delaunay triangulation, an
adaptively refined sphere, noisy and edge-flipped copies of a mesh."""
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


# ---- kinds of session 8 (not in the default list; tools/fresh.py style use) ----

def compact(V, F):
    """Drop the vertices no face uses, renumber."""
    used = sorted({i for t in F for i in t})
    m = {o: k for k, o in enumerate(used)}
    return [V[o] for o in used], [[m[i] for i in t] for t in F]


def masked(nx, ny, keep, W=1.0, H=1.0, fz=lambda x, y: 0.0, seed=None):
    """A flat (or height-field) domain: the cells (i, j) of an nx x ny cell
    grid with keep(i, j) true; diagonals alternate (or random with seed).
    Cells meeting at a corner only must not be kept (non-manifold)."""
    rnd = random.Random(seed)
    vid = lambda i, j: j * (nx + 1) + i
    V = [[W * i / nx, H * j / ny, fz(W * i / nx, H * j / ny)] for j in range(ny + 1) for i in range(nx + 1)]
    F = []
    for j in range(ny):
        for i in range(nx):
            if not keep(i, j):
                continue
            a, b, c, d = vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)
            if (rnd.random() < 0.5) if seed is not None else ((i + j) % 2 == 0):
                F += [[a, b, c], [a, c, d]]
            else:
                F += [[a, b, d], [b, c, d]]
    return compact(V, F)


def comb(teeth=6, nx=72, ny=40):
    """A comb: a spine along the bottom and teeth separated by one-cell slots."""
    w = nx // (2 * teeth)
    return masked(nx, ny, lambda i, j: j < 6 or (i // w) % 2 == 0, W=nx / ny * 1.0)


def lshape(n=44):
    return masked(n, n, lambda i, j: i < n // 2 or j < n // 2)


def spiral(n=48, wall=2, gap=4):
    """A square spiral corridor of width gap cells between walls of wall cells."""
    blocked = set()
    p = wall + gap
    lo, hi = 0, n - 1
    # walls: concentric squares with one opening each, shifted: a maze-spiral
    k = 0
    while hi - lo > 2 * p:
        for t in range(lo, hi + 1):
            for w in range(wall):
                for c in ((t, lo + w), (t, hi - w), (lo + w, t), (hi - w, t)):
                    blocked.add(c)
        # opening of this ring (gap long), on a side that alternates
        side = k % 4
        mid = (lo + hi) // 2
        for t in range(mid - gap // 2, mid + gap - gap // 2):
            for w in range(wall):
                c = [(t, lo + w), (hi - w, t), (t, hi - w), (lo + w, t)][side]
                blocked.discard(c)
        lo += p
        hi -= p
        k += 1
    # keep the outermost ring open: remove the outermost wall so the domain's boundary is the square
    keep = lambda i, j: (i, j) not in blocked or (wall > 0 and (i < wall or j < wall or i >= n - wall or j >= n - wall))
    return masked(n, n, keep)


def perforated(n=56, holes=5, size=3, seed=13):
    """A square plate with holes x holes square holes of size x size cells, placed on a jittered lattice."""
    rnd = random.Random(seed)
    blocked = set()
    step = n // holes
    for a in range(holes):
        for b in range(holes):
            i0 = a * step + 1 + rnd.randrange(max(1, step - size - 1))
            j0 = b * step + 1 + rnd.randrange(max(1, step - size - 1))
            for i in range(i0, i0 + size):
                for j in range(j0, j0 + size):
                    blocked.add((i, j))
    return masked(n, n, lambda i, j: (i, j) not in blocked)


def slab(n=30, holes=((8, 12, 8, 12),), t=0.1, walls=2):
    """A closed slab (top, bottom and walls of height 2t) around a masked
    square with rectangular holes (i0, i1, j0, j1): genus = len(holes)."""
    blocked = {(i, j) for (i0, i1, j0, j1) in holes for i in range(i0, i1) for j in range(j0, j1)}
    keep = lambda i, j: (i, j) not in blocked
    Vt, Ft = masked(n, n, keep)
    nt = len(Vt)
    # boundary edges of the top (each edge used by one face), directed as in the faces
    cnt = {}
    for f in Ft:
        for k in range(3):
            a, b = f[k], f[(k + 1) % 3]
            cnt[(a, b)] = cnt.get((a, b), 0) + 1
    bnd = [(a, b) for (a, b) in cnt if (b, a) not in cnt]
    L = walls + 1  # layers of vertices: 0 = top, walls = bottom... build levels
    V = []
    for l in range(L):
        z = t - 2 * t * l / walls
        V += [[v[0], v[1], z] for v in Vt]
    F = [list(f) for f in Ft] + [[f[0] + walls * nt, f[2] + walls * nt, f[1] + walls * nt] for f in Ft]
    for (a, b) in bnd:
        for l in range(walls):
            a0, b0, a1, b1 = a + l * nt, b + l * nt, a + (l + 1) * nt, b + (l + 1) * nt
            F += [[b0, a0, a1], [b0, a1, b1]]
    return compact(V, F)


def revolution(profile, nu, step_lo, step_hi):
    """A closed surface of revolution about z: profile(s) -> (r, z) for s in
    [0, 1] with r = 0 at both ends (poles); rings at arc-length steps of
    clamp(2 pi r / nu, step_lo, step_hi)."""
    P = [profile(k / 20000) for k in range(20001)]
    rings, acc, target = [], 0.0, 0.0
    for k in range(1, len(P)):
        acc += math.hypot(P[k][0] - P[k - 1][0], P[k][1] - P[k - 1][1])
        if acc >= target and 0 < k < len(P) - 1:
            r = P[k][0]
            if not rings or acc - rings[-1][2] >= min(step_hi, max(step_lo, 2 * math.pi * r / nu)):
                rings.append((r, P[k][1], acc))
    # drop rings too close to the end pole
    total = acc
    while rings and total - rings[-1][2] < 0.5 * min(step_hi, max(step_lo, 2 * math.pi * rings[-1][0] / nu)):
        rings.pop()
    V = [[0, 0, P[0][1]]]
    for j, (r, z, _) in enumerate(rings):
        for i in range(nu):
            u = 2 * math.pi * (i + 0.5 * (j % 2)) / nu
            V.append([r * math.cos(u), r * math.sin(u), z])
    V.append([0, 0, P[-1][1]])
    F, nr, last = [], len(rings), len(V) - 1
    for i in range(nu):
        F.append([0, 1 + i, 1 + (i + 1) % nu])
    for j in range(nr - 1):
        b0, b1 = 1 + j * nu, 1 + (j + 1) * nu
        for i in range(nu):
            i1 = (i + 1) % nu
            if j % 2 == 0:
                F += [[b0 + i, b1 + i, b0 + i1], [b0 + i1, b1 + i, b1 + i1]]
            else:
                F += [[b0 + i, b1 + i, b1 + i1], [b0 + i, b1 + i1, b0 + i1]]
    b0 = 1 + (nr - 1) * nu
    for i in range(nu):
        F.append([b0 + i, last, b0 + (i + 1) % nu])
    return V, F


def dumbbell(neck=0.12, nu=32, gap=1.6):
    """Two unit spheres (centres z = +-gap) joined by a neck of radius neck."""
    def prof(s):
        z = -(gap + 1) + 2 * (gap + 1) * s
        a = math.sqrt(max(0.0, 1 - (abs(z) - gap) ** 2)) if abs(z) >= gap - 1 else 0.0
        b = neck if abs(z) < gap else 0.0
        return ((a ** 8 + b ** 8) ** 0.125, z)
    return revolution(prof, nu, 0.02, 0.15)


def helix(nu=300, nv=6, turns=3, R=1.0, pitch=0.6, w=0.4):
    """A helicoidal ribbon: a strip of width w swept along a helix (normal to the axis)."""
    V, F = [], []
    for i in range(nu):
        t = turns * 2 * math.pi * i / (nu - 1)
        for j in range(nv):
            r = R + w * (j / (nv - 1) - 0.5)
            V.append([r * math.cos(t), r * math.sin(t), pitch * t / (2 * math.pi)])
    for i in range(nu - 1):
        for j in range(nv - 1):
            a = i * nv + j
            F += [[a, a + nv, a + nv + 1], [a, a + nv + 1, a + 1]]
    return V, F


def saddle(n=45, amp=1.0):
    """The monkey saddle z = amp (x^3 - 3 x y^2) on [-1,1]^2."""
    return grid(n, n, lambda i, j: -1 + 2 * i / (n - 1), lambda i, j: -1 + 2 * j / (n - 1),
                lambda x, y: amp * (x ** 3 - 3 * x * y * y))


def delaunay(P):
    """Bowyer-Watson Delaunay triangulation of 2D points (list of (x, y))."""
    n = len(P)
    pts = list(P) + [(-100.0, -100.0), (100.0, -100.0), (0.0, 100.0)]
    tris = [(n, n + 1, n + 2)]

    def circ(t):
        (ax, ay), (bx, by), (cx, cy) = pts[t[0]], pts[t[1]], pts[t[2]]
        d = 2 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
        ux = ((ax * ax + ay * ay) * (by - cy) + (bx * bx + by * by) * (cy - ay) + (cx * cx + cy * cy) * (ay - by)) / d
        uy = ((ax * ax + ay * ay) * (cx - bx) + (bx * bx + by * by) * (ax - cx) + (cx * cx + cy * cy) * (bx - ax)) / d
        return ux, uy, (ax - ux) ** 2 + (ay - uy) ** 2

    C = {tris[0]: circ(tris[0])}
    for k in range(n):
        x, y = pts[k]
        bad = [t for t, (ux, uy, r2) in C.items() if (x - ux) ** 2 + (y - uy) ** 2 < r2]
        edges = {}
        for t in bad:
            del C[t]
            for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                key = tuple(sorted(e))
                edges[key] = None if key in edges else e
        for e in edges.values():
            if e is None:
                continue
            t = (e[0], e[1], k)
            (ax, ay), (bx, by) = pts[e[0]], pts[e[1]]
            if (bx - ax) * (y - ay) - (by - ay) * (x - ax) < 0:
                t = (e[1], e[0], k)
            C[t] = circ(t)
    return [list(t) for t in C if max(t) < n]


def random_delaunay(n=1500, seed=17, fz=lambda x, y: 0.2 * math.sin(5 * x) * math.cos(4 * y)):
    """Delaunay of n random points in [0,1]^2 (plus the square's boundary
    at even spacing), lifted to a height field: an irregular mesh."""
    rnd = random.Random(seed)
    m = int(math.sqrt(n))
    P = [(i / m, 0.0) for i in range(m)] + [(1.0, i / m) for i in range(m)] + \
        [(1 - i / m, 1.0) for i in range(m)] + [(0.0, 1 - i / m) for i in range(m)]
    P += [(0.01 + 0.98 * rnd.random(), 0.01 + 0.98 * rnd.random()) for _ in range(n - len(P))]
    F = delaunay(P)
    return [[x, y, fz(x, y)] for (x, y) in P], F


def adaptive(fn, centre, radii):
    """Refine the faces of a unit-sphere mesh fn whose centroid lies within
    radii[l] of centre at level l (1-to-4, conforming closure by bisection),
    new vertices projected to the unit sphere."""
    V, F = read(fn)
    for rad in radii:
        mid = {}

        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                p = [(V[a][q] + V[b][q]) / 2 for q in range(3)]
                s = math.sqrt(sum(x * x for x in p))
                V.append([x / s for x in p])
                mid[k] = len(V) - 1
            return mid[k]
        ek = lambda a, b: (min(a, b), max(a, b))
        marked = set()
        for f in F:
            c = [sum(V[i][q] for i in f) / 3 for q in range(3)]
            if math.dist(c, centre) < rad:
                marked.update(ek(f[k], f[(k + 1) % 3]) for k in range(3))
        changed = True
        while changed:
            changed = False
            for f in F:
                es = [ek(f[k], f[(k + 1) % 3]) for k in range(3)]
                if sum(e in marked for e in es) == 2:
                    marked.update(es)
                    changed = True
        G = []
        for f in F:
            es = [ek(f[k], f[(k + 1) % 3]) for k in range(3)]
            s = [e in marked for e in es]
            if all(s):
                a, b, c = f
                ab, bc, ca = m(a, b), m(b, c), m(c, a)
                G += [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
            elif any(s):
                k = s.index(True)
                a, b, c = f[k], f[(k + 1) % 3], f[(k + 2) % 3]
                ab = m(a, b)
                G += [[a, ab, c], [ab, b, c]]
            else:
                G.append(f)
        F = G
    return V, F


def noisy(fn, frac, seed=23):
    """Vertices moved by Gaussian noise of frac mean edges (each coordinate)."""
    V, F = read(fn)
    rnd = random.Random(seed)
    L = [math.dist(V[t[k]], V[t[(k + 1) % 3]]) for t in F for k in range(3)]
    s = frac * sum(L) / len(L)
    return [[x + rnd.gauss(0, s) for x in v] for v in V], F


def flipped(fn, frac, seed=29, max_dihedral=0.5):
    """Random edge flips (a fraction frac of the edges tried), each kept
    only if the edge is interior, the new edge is new and the two triangles
    stay nearly coplanar (normals within max_dihedral radians)."""
    V, F = read(fn)
    F = [list(t) for t in F]
    rnd = random.Random(seed)

    def nrm(t):
        a, b, c = (V[i] for i in t)
        u = [b[q] - a[q] for q in range(3)]
        w = [c[q] - a[q] for q in range(3)]
        x = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
        s = math.sqrt(sum(y * y for y in x)) or 1
        return [y / s for y in x]
    edges = {}
    for fi, t in enumerate(F):
        for k in range(3):
            edges.setdefault((t[k], t[(k + 1) % 3]), fi)
    keys = list(edges)
    rnd.shuffle(keys)
    done = 0
    for (a, b) in keys[: int(frac * len(keys))]:
        if (a, b) not in edges or (b, a) not in edges:
            continue
        f0, f1 = edges[(a, b)], edges[(b, a)]
        c = [v for v in F[f0] if v not in (a, b)][0]
        d = [v for v in F[f1] if v not in (a, b)][0]
        if (c, d) in edges or (d, c) in edges or c == d:
            continue
        n0, n1 = nrm([a, b, c]), nrm([b, a, d])
        t0, t1 = [c, d, b], [d, c, a]
        m0, m1 = nrm(t0), nrm(t1)
        dot = lambda p, q: sum(p[i] * q[i] for i in range(3))
        if dot(m0, m1) < math.cos(max_dihedral) or dot(m0, n0) < 0.5 or dot(m1, n1) < 0.5:
            continue
        for t in (F[f0], F[f1]):
            for k in range(3):
                edges.pop((t[k], t[(k + 1) % 3]), None)
        F[f0], F[f1] = t0, t1
        for fi in (f0, f1):
            t = F[fi]
            for k in range(3):
                edges[(t[k], t[(k + 1) % 3])] = fi
        done += 1
    return V, F


def joined(parts):
    """Several (V, F, scale, offset) parts as one mesh."""
    V, F = [], []
    for (V2, F2, s, off) in parts:
        b = len(V)
        V.extend([[v[q] * s + off[q] for q in range(3)] for v in V2])
        F.extend([[t[0] + b, t[1] + b, t[2] + b] for t in F2])
    return V, F


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
    write(p("slab2"), *slab(34, ((7, 14, 10, 24), (20, 27, 10, 24))))
    write(p("slab-thick"), *slab(26, ((5, 11, 7, 19), (15, 21, 7, 19)), t=0.25, walls=12))
    write(p("cube-1e-3"), *scaled(p("cube16"), 1e-3))
    write(p("bumpy-1e4"), *scaled(p("sphere-bumpy"), 1e4))
    shared = os.environ.get("GEOSEP_SHARED", "")
    for name in ("homer", "rocker-arm"):
        src = os.path.join(shared, "meshes", name + ".obj")
        if shared and os.path.exists(src):
            subprocess.run([g, "subdivide", src, "-o", p(name + "-sub1")], check=True, stdout=subprocess.DEVNULL)


if __name__ == "__main__":
    main()
