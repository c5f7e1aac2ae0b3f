#!/usr/bin/env python3
"""How much of the held-out views a model made from the source views alone could cover.

    colmap model_converter --input_path MODEL --output_path TXT --output_type TXT
    bench/holdout_ceiling.py TXT MESH.obj [--holdout 4] [--depth-tolerance 0.01]

A reference mesh (e.g. ../shared/data/anchors/openmvs-fountain-P11, made by OpenMVS from every
photo, in the frame of its sparse/ model) is rasterised into every registered view with a
z-buffer. For each held-out view (every N-th by name, as `varsfm run --holdout N` picks them),
each pixel the mesh covers is followed to its surface point and into every source view, where it
counts as seen when it falls inside the image at the depth of that view's z-buffer (within the
tolerance, relative). Prints, per held-out view and on average, the share of its pixels that the
mesh covers and that >= 1, >= 2 and >= 3 source views see: multi-view stereo needs two views of a
surface, so the ">= 2" share bounds the held-out coverage that bench/dense reports.
"""
import argparse

import numpy as np


def quaternion_matrix(w, x, y, z):
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def read_views(model):
    """name -> (R, t, width, height, params) of a COLMAP TXT model (SIMPLE_RADIAL/RADIAL/PINHOLE-like:
    f, cx, cy[, k1[, k2]])."""
    cameras = {}
    for line in open(f"{model}/cameras.txt"):
        if line.startswith("#") or not line.strip():
            continue
        p = line.split()
        params = list(map(float, p[4:])) + [0.0, 0.0]
        cameras[int(p[0])] = (int(p[2]), int(p[3]), params)
    views = {}
    lines = [l for l in open(f"{model}/images.txt") if not l.startswith("#")]
    for i in range(0, len(lines), 2):
        p = lines[i].split()
        if len(p) < 10:
            continue
        R = quaternion_matrix(*map(float, p[1:5]))
        t = np.array(list(map(float, p[5:8])))
        views[p[9]] = (R, t) + cameras[int(p[8])]
    return views


def read_obj(path):
    vertices, faces = [], []
    for line in open(path):
        if line.startswith("v "):
            vertices.append(list(map(float, line.split()[1:4])))
        elif line.startswith("f "):
            faces.append([int(s.split("/")[0]) - 1 for s in line.split()[1:4]])
    return np.array(vertices), np.array(faces)


def project(view, X):
    R, t, _, _, (f, cx, cy, k1, k2, *_) = view
    Xc = X @ R.T + t
    z = Xc[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        xn, yn = Xc[:, 0] / z, Xc[:, 1] / z
    r2 = xn * xn + yn * yn
    s = 1 + k1 * r2 + k2 * r2 * r2
    return f * xn * s + cx, f * yn * s + cy, z


def depth_map(view, vertices, faces):
    """The nearest depth per pixel centre (inf where the mesh is not); faces with a vertex behind
    the camera are skipped."""
    width, height = view[2], view[3]
    u, v, z = project(view, vertices)
    depth = np.full((height, width), np.inf)
    for (au, bu, cu), (av, bv, cv), zs in zip(u[faces], v[faces], z[faces]):
        if (zs <= 0).any():
            continue
        x0, x1 = max(int(np.floor(min(au, bu, cu))), 0), min(int(np.ceil(max(au, bu, cu))), width - 1)
        y0, y1 = max(int(np.floor(min(av, bv, cv))), 0), min(int(np.ceil(max(av, bv, cv))), height - 1)
        den = (bv - cv) * (au - cu) + (cu - bu) * (av - cv)
        if x0 > x1 or y0 > y1 or abs(den) < 1e-12:
            continue
        xs, ys = np.meshgrid(np.arange(x0, x1 + 1) + 0.5, np.arange(y0, y1 + 1) + 0.5)
        l1 = ((bv - cv) * (xs - cu) + (cu - bu) * (ys - cv)) / den
        l2 = ((cv - av) * (xs - cu) + (au - cu) * (ys - cv)) / den
        l3 = 1 - l1 - l2
        inside = (l1 >= 0) & (l2 >= 0) & (l3 >= 0)
        zz = 1 / (l1 / zs[0] + l2 / zs[1] + l3 / zs[2])  # perspective-correct depth
        window = depth[y0:y1 + 1, x0:x1 + 1]
        nearer = inside & (zz < window)
        window[nearer] = zz[nearer]
    return depth


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("model", help="COLMAP TXT model (cameras.txt, images.txt)")
    parser.add_argument("mesh", help="reference mesh (OBJ) in the model's frame")
    parser.add_argument("--holdout", type=int, default=4)
    parser.add_argument("--depth-tolerance", type=float, default=0.01)
    args = parser.parse_args()
    views = read_views(args.model)
    vertices, faces = read_obj(args.mesh)
    names = sorted(views)
    held_out = names[::args.holdout]
    maps = {name: depth_map(views[name], vertices, faces) for name in names}
    shares = []
    for name in held_out:
        R, t, width, height, (f, cx, cy, *_) = views[name]
        ys, xs = np.nonzero(np.isfinite(maps[name]))
        z = maps[name][ys, xs]
        # The distortion of a reference model is small; the pixel ray is taken as a pinhole's.
        X = (np.stack([(xs + 0.5 - cx) / f * z, (ys + 0.5 - cy) / f * z, z], 1) - t) @ R
        seen = np.zeros(len(z), int)
        for source in names:
            if source in held_out:
                continue
            u, v, zs = project(views[source], X)
            w, h = views[source][2], views[source][3]
            inside = (zs > 0) & (u >= 0) & (v >= 0) & (u < w) & (v < h)
            ui = np.where(inside, u, 0).astype(int)
            vi = np.where(inside, v, 0).astype(int)
            seen += inside & (np.abs(maps[source][vi, ui] - zs) < args.depth_tolerance * zs)
        n = width * height
        share = [len(z) / n] + [np.sum(seen >= k) / n for k in (1, 2, 3)]
        shares.append(share)
        print(f"{name}: mesh {100 * share[0]:.1f} %, seen by >= 1 source view {100 * share[1]:.1f} %,"
              f" >= 2 {100 * share[2]:.1f} %, >= 3 {100 * share[3]:.1f} %")
    m = 100 * np.mean(shares, 0)
    print(f"mean over {len(held_out)} held-out views: mesh {m[0]:.1f} %, >= 1 {m[1]:.1f} %, "
          f">= 2 {m[2]:.1f} %, >= 3 {m[3]:.1f} %")


if __name__ == "__main__":
    main()
