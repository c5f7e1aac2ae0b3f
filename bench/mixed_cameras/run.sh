#!/bin/bash
# bench/mixed_cameras/run.sh BIN WORK: fountain-P11 as if taken by several cameras, each set
# reconstructed (extract, match, map with default settings) and scored against the ground truth.
#   resized  every third photo upscaled to 1600x1067 (another phone's resolution)
#   cropped  every third photo cropped to its centre 700x450 (a digital zoom)
#   harsh    every third photo cropped to its bottom-right 524x383 (a corner cut out in an
#            editor: the principal point 55 % of the larger side from the crop's centre)
#   mixed    the photos cycle through original, upscaled and the harsh crop; 0005 also grey
#   zoom     every photo cut to its central 1/z and upscaled back (a digital zoom, z = 1, 1.5, 2,
#            2.5 in turn)
# Camera centre and rotation errors are measured for every photo; `evaluate` leaves out the
# intrinsics of a photo whose aspect ratio differs from the ground truth's (a crop).
set -euo pipefail
BIN=$(realpath "$1"); WORK=$2
DATA=${VARSFM_SHARED_DATA:-$(dirname "$0")/../../../shared/data}/strecha/fountain-P11
mkdir -p "$WORK"
/usr/bin/python3 - "$DATA/images" "$WORK" <<'PY'
import cv2, glob, os, sys
src, work = sys.argv[1], sys.argv[2]
for i, f in enumerate(sorted(glob.glob(src + '/*.jpg'))):
    im, name = cv2.imread(f), os.path.basename(f)
    third = i % 3
    sets = {
        'resized': cv2.resize(im, (1600, 1067), interpolation=cv2.INTER_CUBIC) if third == 1 else im,
        'cropped': im[150:600, 200:900] if third == 2 else im,
        'harsh': im[300:, 500:] if third == 2 else im,
    }
    mixed = {0: im, 1: cv2.resize(im, (1600, 1067), interpolation=cv2.INTER_AREA), 2: im[300:, 500:]}[third]
    if i == 5:
        mixed = cv2.cvtColor(cv2.cvtColor(mixed, cv2.COLOR_BGR2GRAY), cv2.COLOR_GRAY2BGR)
    sets['mixed'] = mixed
    z = [1.0, 1.5, 2.0, 2.5][i % 4]
    h, w = im.shape[:2]
    cw, ch = int(round(w / z)), int(round(h / z))
    x0, y0 = (w - cw) // 2, (h - ch) // 2
    sets['zoom'] = cv2.resize(im[y0:y0 + ch, x0:x0 + cw], (w, h), interpolation=cv2.INTER_CUBIC)
    for tag, image in sets.items():
        os.makedirs(f'{work}/{tag}', exist_ok=True)
        cv2.imwrite(f'{work}/{tag}/{name}', image, [cv2.IMWRITE_JPEG_QUALITY, 92])
PY
for set in resized cropped harsh mixed zoom; do
  out=$WORK/$set.out; rm -rf "$out"
  "$BIN" run "$WORK/$set" "$out" --until sparse -q
  echo "== $set"
  "$BIN" evaluate "$out/sparse/0" --gt "$DATA/gt" 2>&1 | sed -n 1,9p
done
