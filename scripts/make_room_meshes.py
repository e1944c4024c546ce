#!/usr/bin/env python3
"""Writes the meshes of scenes/room.toml into scenes/meshes/room/ (closed, outward, in metres).

The furniture, the kettle, the vase and the F-shape are generated here. The Stanford bunny,
the Stanford dragon and Newell's teapot come from public repositories (scenes/meshes/room/
SOURCES.md) and are made watertight with VTK (Debian python3-vtk9): points welded, holes
filled (a fan around each boundary loop's centroid), the largest piece kept, decimated to a haptic-friendly size, normals made consistent
and outward. Run once; its output is committed:

    python3 scripts/make_room_meshes.py BUNNY.obj DRAGON.obj TEAPOT.obj
"""
import math
import sys
from pathlib import Path

import numpy as np

OUT = Path(__file__).resolve().parent.parent / "scenes" / "meshes" / "room"


def write_obj(path, vertices, triangles, comment):
    with open(path, "w") as f:
        f.write(f"# {comment}\n")
        for v in vertices:
            f.write("v {:.6f} {:.6f} {:.6f}\n".format(*v))
        for t in triangles:
            f.write("f {} {} {}\n".format(*(int(i) + 1 for i in t)))


def boxes(specs):
    """Disjoint axis-aligned boxes (min, max) as one closed, outward surface."""
    vertices, triangles = [], []
    faces = [(0, 2, 1), (0, 3, 2), (4, 5, 6), (4, 6, 7), (0, 1, 5), (0, 5, 4),
             (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6), (3, 0, 4), (3, 4, 7)]
    for lo, hi in specs:
        base = len(vertices)
        for z in (lo[2], hi[2]):
            vertices += [(lo[0], lo[1], z), (hi[0], lo[1], z), (hi[0], hi[1], z), (lo[0], hi[1], z)]
        triangles += [(base + a, base + b, base + c) for a, b, c in faces]
    return np.array(vertices), np.array(triangles)


def revolution(profile, segments=48):
    """A closed surface of revolution about z from (r, z) points, bottom pole to top pole."""
    rings = profile[1:-1]
    vertices = [(0.0, 0.0, profile[0][1])]
    for r, z in rings:
        for k in range(segments):
            a = 2 * math.pi * k / segments
            vertices.append((r * math.cos(a), r * math.sin(a), z))
    vertices.append((0.0, 0.0, profile[-1][1]))
    top = len(vertices) - 1
    tris = []
    ring = lambda i, k: 1 + i * segments + k % segments
    for k in range(segments):
        tris.append((0, ring(0, k + 1), ring(0, k)))
    for i in range(len(rings) - 1):
        for k in range(segments):
            a, b, c, d = ring(i, k), ring(i, k + 1), ring(i + 1, k + 1), ring(i + 1, k)
            tris += [(a, b, c), (a, c, d)]
    n = len(rings) - 1
    for k in range(segments):
        tris.append((top, ring(n, k), ring(n, k + 1)))
    return np.array(vertices), np.array(tris)


def voxel_surface(cells, size):
    """The closed boundary of a union of unit cells (x, y, z) scaled by size: shared faces dropped,
    shared corners welded, each boundary square as two outward triangles."""
    filled = set(cells)
    index, vertices, tris = {}, [], []

    def vid(p):
        if p not in index:
            index[p] = len(vertices)
            vertices.append(tuple(c * size for c in p))
        return index[p]

    for (x, y, z) in cells:
        for axis in range(3):
            for side in (0, 1):
                n = [0, 0, 0]
                n[axis] = 1 if side else -1
                if (x + n[0], y + n[1], z + n[2]) in filled:
                    continue
                u, v = (axis + 1) % 3, (axis + 2) % 3
                corner = [x, y, z]
                corner[axis] += side
                quad = []
                for du, dv in ((0, 0), (1, 0), (1, 1), (0, 1)):
                    p = list(corner)
                    p[u] += du
                    p[v] += dv
                    quad.append(vid(tuple(p)))
                a, b, c, d = quad
                tris += [(a, b, c), (a, c, d)] if side else [(a, c, b), (a, d, c)]
    return np.array(vertices, dtype=float), np.array(tris)


def fan_fill(v, t):
    """Closes each remaining boundary loop with a fan around its centroid (holes VTK's filler
    leaves, such as the bunny's non-planar base)."""
    nxt = {}
    edges = {}
    for a, b, c in t:
        for p, q in ((a, b), (b, c), (c, a)):
            edges[(p, q)] = edges.get((p, q), 0) + 1
    for (p, q) in edges:
        if (q, p) not in edges:
            nxt[q] = p  # the loop runs against the surface's own direction
    v, t = list(map(tuple, v)), list(map(tuple, t))
    while nxt:
        start = next(iter(nxt))
        loop = [start]
        while nxt.get(loop[-1], start) != start:
            loop.append(nxt[loop[-1]])
            if len(loop) > len(nxt):
                sys.exit("a boundary loop does not close (a non-manifold boundary vertex)")
        for p in loop:
            del nxt[p]
        centre = len(v)
        v.append(tuple(np.mean([v[i] for i in loop], axis=0)))
        for i in range(len(loop)):
            t.append((loop[i], loop[(i + 1) % len(loop)], centre))
    return np.array(v, dtype=float), np.array(t)


def split_pinched_vertices(v, t):
    """A vertex whose triangles form several fans (two surface sheets touching at a point, as
    where two filled holes meet) becomes one vertex per fan, so the surface is a manifold."""
    v, t = list(map(tuple, v)), [list(x) for x in t]
    around = {}
    for i, tri in enumerate(t):
        for k in range(3):
            around.setdefault(tri[k], []).append(i)
    for vertex, tris in around.items():
        # Fans: triangles around the vertex joined through their shared edges at it.
        others = {i: {x for x in t[i] if x != vertex} for i in tris}
        fans, seen = [], set()
        for i in tris:
            if i in seen:
                continue
            fan, stack = [], [i]
            seen.add(i)
            while stack:
                j = stack.pop()
                fan.append(j)
                for k in tris:
                    if k not in seen and others[j] & others[k]:
                        seen.add(k)
                        stack.append(k)
            fans.append(fan)
        for fan in fans[1:]:
            copy = len(v)
            v.append(v[vertex])
            for j in fan:
                t[j] = [copy if x == vertex else x for x in t[j]]
    return np.array(v, dtype=float), np.array(t)


def to_vtk(v, t):
    import vtk
    from vtk.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
    pd = vtk.vtkPolyData()
    pts = vtk.vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(v), deep=True))
    pd.SetPoints(pts)
    cells = np.hstack([np.full((len(t), 1), 3), t]).astype(np.int64).ravel()
    polys = vtk.vtkCellArray()
    polys.SetCells(len(t), numpy_to_vtkIdTypeArray(cells, deep=True))
    pd.SetPolys(polys)
    return pd


def scanned(path, target_triangles, longest):
    """A scanned mesh made watertight, decimated, oriented outward, standing on z = 0 and centred
    in x and y, its longest side `longest` metres."""
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    reader = vtk.vtkOBJReader()
    reader.SetFileName(str(path))
    clean = vtk.vtkCleanPolyData()
    clean.SetInputConnection(reader.GetOutputPort())
    clean.SetTolerance(0.0)
    tri = vtk.vtkTriangleFilter()
    tri.SetInputConnection(clean.GetOutputPort())
    largest = vtk.vtkPolyDataConnectivityFilter()
    largest.SetInputConnection(tri.GetOutputPort())
    largest.SetExtractionModeToLargestRegion()
    largest.Update()
    welded = vtk.vtkCleanPolyData()
    welded.SetInputConnection(largest.GetOutputPort())
    welded.Update()
    w = welded.GetOutput()
    closed = to_vtk(*fan_fill(vtk_to_numpy(w.GetPoints().GetData()).astype(float),
                              vtk_to_numpy(w.GetPolys().GetData()).reshape(-1, 4)[:, 1:]))
    faces = closed.GetNumberOfCells()
    clean2 = vtk.vtkCleanPolyData()
    if target_triangles < faces:
        decimate = vtk.vtkQuadricDecimation()
        decimate.SetInputData(closed)
        decimate.SetTargetReduction(1.0 - target_triangles / faces)
        decimate.VolumePreservationOn()
        clean2.SetInputConnection(decimate.GetOutputPort())
    else:
        clean2.SetInputData(closed)
    normals = vtk.vtkPolyDataNormals()
    normals.SetInputConnection(clean2.GetOutputPort())
    normals.ConsistencyOn()
    normals.AutoOrientNormalsOn()
    normals.SplittingOff()
    normals.Update()
    out = normals.GetOutput()
    edges = vtk.vtkFeatureEdges()
    edges.SetInputData(out)
    edges.BoundaryEdgesOn()
    edges.NonManifoldEdgesOn()
    edges.FeatureEdgesOff()
    edges.ManifoldEdgesOff()
    edges.Update()
    if edges.GetOutput().GetNumberOfCells() != 0:
        sys.exit(f"{path}: {edges.GetOutput().GetNumberOfCells()} open or non-manifold edges remain")
    v, t = split_pinched_vertices(vtk_to_numpy(out.GetPoints().GetData()).astype(float),
                                  vtk_to_numpy(out.GetPolys().GetData()).reshape(-1, 4)[:, 1:])
    v -= np.array([(v[:, 0].min() + v[:, 0].max()) / 2, (v[:, 1].min() + v[:, 1].max()) / 2, v[:, 2].min()])
    v *= longest / (v.max(axis=0) - v.min(axis=0)).max()
    return v, t


def z_up(v, t):
    """Y-up scans stood on z: (x, y, z) → (x, −z, y), a proper rotation."""
    return np.stack([v[:, 0], -v[:, 2], v[:, 1]], axis=1), t


def check(name, v, t):
    e = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    _, counts = np.unique(e, axis=0, return_counts=True)
    assert (counts == 2).all(), f"{name}: not closed"
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6
    assert volume > 0, f"{name}: inward"
    print(f"{name}: {len(v)} vertices, {len(t)} triangles, volume {volume * 1e6:.1f} cm³")


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    generated = "generated by scripts/make_room_meshes.py"
    shapes = {}
    legs = [((x, y, 0.0), (x + 0.05, y + 0.05, 0.719)) for x in (-0.58, 0.53) for y in (-0.38, 0.33)]
    shapes["table"] = boxes([((-0.6, -0.4, 0.72), (0.6, 0.4, 0.76))] + legs)
    chair_legs = [((x, y, 0.0), (x + 0.04, y + 0.04, 0.429)) for x in (-0.225, 0.185) for y in (-0.225, 0.185)]
    shapes["chair"] = boxes([((-0.225, -0.225, 0.43), (0.225, 0.225, 0.47)),
                             ((-0.225, 0.196, 0.471), (0.225, 0.225, 0.92))] + chair_legs)
    shapes["sofa"] = boxes([((-0.9, -0.4, 0.0), (0.9, 0.4, 0.4)), ((-0.9, 0.25, 0.401), (0.9, 0.4, 0.8)),
                            ((-0.9, -0.4, 0.401), (-0.75, 0.249, 0.65)), ((0.75, -0.4, 0.401), (0.9, 0.249, 0.65))])
    shapes["kettle"] = revolution([(0, 0), (0.07, 0.0), (0.095, 0.03), (0.1, 0.08), (0.09, 0.14), (0.06, 0.17),
                                   (0.045, 0.18), (0.012, 0.185), (0.012, 0.205), (0.0, 0.21)])
    shapes["vase"] = revolution([(0, 0), (0.05, 0.0), (0.075, 0.06), (0.08, 0.12), (0.05, 0.22), (0.03, 0.27),
                                 (0.045, 0.3), (0.0, 0.3)])
    f_cells = [(0, 0, z) for z in range(6)] + [(1, 0, 5), (2, 0, 5), (1, 0, 3)]
    v, t = voxel_surface(f_cells, 0.03)
    shapes["f_shape"] = (v - np.array([0.045, 0.015, 0.0]), t)
    for name, (v, t) in shapes.items():
        check(name, v, t)
        write_obj(OUT / f"{name}.obj", v, t, generated)
    if len(sys.argv) == 4:
        for name, path, target, longest in (("bunny", sys.argv[1], 20000, 0.15), ("dragon", sys.argv[2], 100000, 0.22),
                                            ("teapot", sys.argv[3], 6000, 0.2)):
            v, t = z_up(*scanned(path, target, longest))
            lo, hi = v.min(axis=0), v.max(axis=0)
            v -= np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, lo[2]])
            check(name, v, t)
            write_obj(OUT / f"{name}.obj", v, t, f"made watertight by scripts/make_room_meshes.py; source in SOURCES.md")


if __name__ == "__main__":
    main()
