#!/usr/bin/env python3
"""What resampling a photo at a half-pixel offset loses, by interpolation method.

Every photo the 3dgs export writes is resampled (undistortion, and the centred principal point's
sub-pixel crop). The truth at a half-pixel offset is made from the photo itself: area-averaged to
a quarter of its size at two offsets 2 full-size pixels apart (half a pixel at the quarter size);
the first is then resampled onto the second's grid with each OpenCV method and compared with it
(PSNR over all but an 8-pixel border).

Usage: bench/resampling_loss.py PHOTO...
"""
import sys

import cv2
import numpy as np

METHODS = [("linear", cv2.INTER_LINEAR), ("cubic", cv2.INTER_CUBIC),
           ("lanczos4", cv2.INTER_LANCZOS4)]


def psnr(a, b):
    return 10 * np.log10(255.0 ** 2 / np.mean((a.astype(float) - b.astype(float)) ** 2))


scores = {name: [] for name, _ in METHODS}
for path in sys.argv[1:]:
    photo = cv2.imread(path).astype(np.float32)
    h, w = (s - s % 4 for s in photo.shape[:2])
    photo = photo[:h, :w]
    small = cv2.resize(photo, (w // 4, h // 4), interpolation=cv2.INTER_AREA)
    shifted = np.roll(photo, (-2, -2), axis=(0, 1))
    truth = cv2.resize(shifted, (w // 4, h // 4), interpolation=cv2.INTER_AREA)
    grid_x, grid_y = np.meshgrid(np.arange(w // 4, dtype=np.float32) + 0.5,
                                 np.arange(h // 4, dtype=np.float32) + 0.5)
    for name, method in METHODS:
        resampled = np.clip(cv2.remap(small, grid_x, grid_y, method,
                                      borderMode=cv2.BORDER_REPLICATE), 0, 255)
        scores[name].append(psnr(resampled[8:-8, 8:-8], truth[8:-8, 8:-8]))
for name, values in scores.items():
    print(f"{name}: " + " ".join(f"{v:.2f}" for v in values) + f"  mean {np.mean(values):.2f} dB")
