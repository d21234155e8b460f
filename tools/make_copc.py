#!/usr/bin/env python3
"""Writes the COPC test fixtures in data/ (Cloud Optimized Point Cloud, https://copc.io).

    pip install copclib laspy lazrs numpy     # copclib 2.6, laspy 2.7, lazrs 0.8
    python3 tools/make_copc.py                # writes data/courtyard.copc.laz
    python3 tools/make_copc.py --autzen       # and data/autzen_trim.copc.laz (not committed)

The octree is built here the way PDAL's and untwine's COPC writers build it: the root cube
encloses the points; level d keeps at most one point per cell of a grid of GRID cells per
side of each node (cell size = spacing / 2^d, with spacing = 2 * halfsize / GRID); the points
a level does not keep go down to the next level; the deepest level keeps all that remain.
Every point lands in exactly one node, so the union of all nodes is the input cloud.
copclib compresses each node as its own LAZ chunk and writes the hierarchy EVLR.

The output is deterministic (fixed random seed).

- courtyard.copc.laz: a generated scene for view-dependent detail: 60 m x 60 m of ground
  a 2 m wall around it and ten 6 m pillars, all sampled every 0.1 m, point format 6.
- autzen_trim.copc.laz (with --autzen): data/autzen_trim.laz (point format 3) as COPC (point format 7, the
  same coordinates, colour, intensity, returns, classes and GPS time).
"""

import os
import sys

import numpy as np

import copclib

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
DATA = os.path.join(ROOT, "data")
SEED = 15


def courtyard():
    """Columns of the generated scene: x, y, z, intensity, classification."""
    rng = np.random.default_rng(SEED)
    step = 0.1
    g = np.arange(-30.0, 30.0 + 1e-9, step)
    gx, gy = np.meshgrid(g, g)
    gx = gx.ravel() + rng.uniform(-0.01, 0.01, gx.size)
    gy = gy.ravel() + rng.uniform(-0.01, 0.01, gy.size)
    # Gentle undulation so the ground is not one plane.
    gz = 0.3 * np.sin(gx / 7.0) * np.cos(gy / 9.0)
    parts = [(gx, gy, gz, np.full(gx.size, 2))]
    # A 2 m wall along the ground's edge, sampled every 0.1 m.
    s = np.arange(-30.0, 30.0, step)
    h = np.arange(0.0, 2.0 + 1e-9, step)
    ss, hh = np.meshgrid(s, h)
    ss, hh = ss.ravel(), hh.ravel()
    for wx, wy in [(ss, np.full_like(ss, -30.0)), (ss, np.full_like(ss, 30.0)),
                   (np.full_like(ss, -30.0), ss), (np.full_like(ss, 30.0), ss)]:
        parts.append((wx, wy, hh, np.full(ss.size, 6)))
    # Pillars 0.5 m in radius, 6 m high, 5-20 m from the centre.
    angles = np.arange(0.0, 2 * np.pi, 0.1 / 0.5)
    heights = np.arange(0.0, 6.0 + 1e-9, 0.1)
    aa, hh = np.meshgrid(angles, heights)
    aa, hh = aa.ravel(), hh.ravel()
    for i in range(10):
        d = 5.0 + 1.5 * i
        bearing = i * 2.4
        cx, cy = d * np.cos(bearing), d * np.sin(bearing)
        parts.append((cx + 0.5 * np.cos(aa), cy + 0.5 * np.sin(aa), hh, np.full(aa.size, 6)))
    x = np.concatenate([p[0] for p in parts])
    y = np.concatenate([p[1] for p in parts])
    z = np.concatenate([p[2] for p in parts])
    cls = np.concatenate([p[3] for p in parts]).astype(np.uint8)
    intensity = (1000 + 200 * cls.astype(np.int64)).astype(np.uint16)
    return {"x": x, "y": y, "z": z, "intensity": intensity, "classification": cls}


def autzen():
    """Columns of data/autzen_trim.laz."""
    import laspy

    f = laspy.read(os.path.join(DATA, "autzen_trim.laz"))
    return {
        "x": np.asarray(f.x, dtype=np.float64),
        "y": np.asarray(f.y, dtype=np.float64),
        "z": np.asarray(f.z, dtype=np.float64),
        "intensity": np.asarray(f.intensity),
        "classification": np.asarray(f.classification),
        "return_number": np.asarray(f.return_number),
        "number_of_returns": np.asarray(f.number_of_returns),
        "gps_time": np.asarray(f.gps_time),
        "red": np.asarray(f.red),
        "green": np.asarray(f.green),
        "blue": np.asarray(f.blue),
    }


def octree(xyz, grid, max_depth, rng):
    """(centre, halfsize, spacing, {key: point indices}) for points `xyz` (n x 3)."""
    lo, hi = xyz.min(axis=0), xyz.max(axis=0)
    centre = (lo + hi) / 2
    halfsize = float((hi - lo).max()) / 2 * 1.001 + 1e-6
    spacing = 2 * halfsize / grid
    base = centre - halfsize
    nodes = {}
    remaining = rng.permutation(len(xyz))
    for depth in range(max_depth + 1):
        if remaining.size == 0:
            break
        p = xyz[remaining] - base
        node_size = 2 * halfsize / 2**depth
        node = np.clip((p // node_size).astype(np.int64), 0, 2**depth - 1)
        if depth < max_depth:
            cell = np.clip((p // (spacing / 2**depth)).astype(np.int64), 0, grid * 2**depth - 1)
            flat = (cell[:, 0] * (grid << depth) + cell[:, 1]) * (grid << depth) + cell[:, 2]
            _, first = np.unique(flat, return_index=True)
            keep = np.zeros(remaining.size, dtype=bool)
            keep[first] = True
        else:
            keep = np.ones(remaining.size, dtype=bool)
        kept, knode = remaining[keep], node[keep]
        order = np.lexsort((knode[:, 2], knode[:, 1], knode[:, 0]))
        kept, knode = kept[order], knode[order]
        bounds = np.flatnonzero(np.any(np.diff(knode, axis=0) != 0, axis=1)) + 1
        for idx in np.split(np.arange(kept.size), bounds):
            k = knode[idx[0]]
            # Input order within a node: neighbours stay together and compress well.
            nodes[(depth, int(k[0]), int(k[1]), int(k[2]))] = np.sort(kept[idx])
        remaining = remaining[~keep]
    return centre, halfsize, spacing, nodes


def write(path, cols, point_format, grid, max_depth):
    rng = np.random.default_rng(SEED)
    xyz = np.stack([cols["x"], cols["y"], cols["z"]], axis=1)
    centre, halfsize, spacing, nodes = octree(xyz, grid, max_depth, rng)
    lo = xyz.min(axis=0)
    scale = copclib.Vector3(0.001, 0.001, 0.001)
    offset = copclib.Vector3(*[float(np.floor(v)) for v in lo])
    cfg = copclib.CopcConfigWriter(point_format, scale, offset)
    header = cfg.las_header
    header.min = copclib.Vector3(*xyz.min(axis=0))
    header.max = copclib.Vector3(*xyz.max(axis=0))
    info = cfg.copc_info
    info.center_x, info.center_y, info.center_z = (float(v) for v in centre)
    info.halfsize = halfsize
    info.spacing = spacing
    if os.path.exists(path):
        os.remove(path)
    writer = copclib.FileWriter(path, cfg)
    fields = [k for k in cols if k not in ("x", "y", "z")]
    for key in sorted(nodes):
        pts = copclib.Points(point_format)
        for i in nodes[key]:
            p = pts.CreatePoint()
            p.x, p.y, p.z = float(xyz[i, 0]), float(xyz[i, 1]), float(xyz[i, 2])
            p.return_number = 1
            p.number_of_returns = 1
            for name in fields:
                setattr(p, name, cols[name][i].item())
            pts.AddPoint(p)
        writer.AddNode(copclib.VoxelKey(*key), pts)
    writer.Close()
    depth = max(k[0] for k in nodes)
    print(f"wrote {path}: {len(xyz)} points, {len(nodes)} nodes, depth {depth}, "
          f"spacing {spacing:.4f} m, {os.path.getsize(path)} bytes")


def main():
    write(os.path.join(DATA, "courtyard.copc.laz"), courtyard(), 6, grid=32, max_depth=5)
    if "--autzen" in sys.argv:
        # 1.1 MB: not committed; real aerial data as COPC for trying the reader by hand.
        write(os.path.join(DATA, "autzen_trim.copc.laz"), autzen(), 7, grid=64, max_depth=4)
    return 0


if __name__ == "__main__":
    sys.exit(main())
