#!/usr/bin/env python3
"""What a loader that ignores cx, cy sees in an exported COLMAP model.

3D Gaussian Splatting's reference loader takes a PINHOLE camera's field of view from its focal
lengths and size and builds a symmetric frustum: the principal point is taken to be the image
centre. For each model given, prints the mean distance of the principal points from the image
centres and the reprojection error of every observation with the principal point moved there.

Usage: bench/gs_loader_check.py MODEL_DIR...   (COLMAP models; needs `colmap` for the text form)
"""
import subprocess
import sys
import tempfile

import numpy as np
from scipy.spatial.transform import Rotation


def read_text_model(model_dir):
    out = tempfile.mkdtemp()
    subprocess.run(["colmap", "model_converter", "--input_path", model_dir, "--output_path", out,
                    "--output_type", "TXT"], check=True, capture_output=True)
    rows = lambda name: [l.split() for l in open(f"{out}/{name}") if not l.startswith("#")]
    cameras = {int(p[0]): (int(p[2]), int(p[3]), [float(x) for x in p[4:8]])
               for p in rows("cameras.txt")}
    points = {int(p[0]): np.array([float(x) for x in p[1:4]]) for p in rows("points3D.txt")}
    image_rows = rows("images.txt")
    return cameras, points, list(zip(image_rows[0::2], image_rows[1::2]))


def centred_loader_errors(model_dir):
    cameras, points, images = read_text_model(model_dir)
    offsets, errors = [], []
    for header, observations in images:
        qw, qx, qy, qz = (float(x) for x in header[1:5])
        t = np.array([float(x) for x in header[5:8]])
        w, h, (fx, fy, cx, cy) = cameras[int(header[8])]
        offsets.append(np.hypot(cx - w / 2, cy - h / 2))
        R = Rotation.from_quat([qx, qy, qz, qw]).as_matrix()
        for k in range(0, len(observations), 3):
            point_id = int(observations[k + 2])
            if point_id < 0:
                continue
            X = R @ points[point_id] + t
            u, v = fx * X[0] / X[2] + w / 2, fy * X[1] / X[2] + h / 2
            errors.append(np.hypot(u - float(observations[k]), v - float(observations[k + 1])))
    return np.mean(offsets), np.median(errors), np.mean(errors)


for model in sys.argv[1:]:
    offset, median, mean = centred_loader_errors(model)
    print(f"{model}: principal point {offset:.2f} px off centre (mean); reprojection error with "
          f"cx, cy ignored: median {median:.2f} px, mean {mean:.2f} px")
