"""Shared helpers of the whole-run benchmark scripts (bench/table3, bench/growth, bench/scale).

Standard library only. Every number these scripts report comes from a command they ran: stage
times are wall-clock seconds (plus the CPU seconds of the child process, which say more on a
loaded machine), reprojection errors are recomputed here from each model's text files so that
varsfm and COLMAP are measured by the same code, and accuracy against ground truth comes from
`varsfm evaluate` (which reads COLMAP's models too).
"""
import json
import math
import os
import shutil
import sqlite3
import subprocess
import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
IMAGE_EXTENSIONS = {".jpg", ".jpeg", ".png", ".tif", ".tiff", ".bmp", ".ppm", ".pgm"}
PAIR_ID_FACTOR = 2147483647  # COLMAP's pair id: id1 * 2147483647 + id2 with id1 < id2


def log(msg):
    print(f"[{time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


class CommandFailed(Exception):
    pass


def timed(cmd, log_path, env=None, timeout=None):
    """Runs cmd (a list), its output to log_path; returns (wall s, CPU s of the child).
    Raises CommandFailed when it fails or runs past timeout seconds (then it is killed)."""
    m = measured(cmd, log_path, env, timeout)
    return m["wall_s"], m["cpu_s"]


def measured(cmd, log_path, env=None, timeout=None):
    """As timed(), returning {"wall_s", "cpu_s", "peak_mb"} (the child's peak resident memory)."""
    log_path = Path(log_path)
    log_path.parent.mkdir(parents=True, exist_ok=True)
    with open(log_path, "w") as out:
        out.write("$ " + " ".join(map(str, cmd)) + "\n")
        out.flush()
        start = time.monotonic()
        proc = subprocess.Popen([str(c) for c in cmd], stdout=out, stderr=subprocess.STDOUT,
                                env=env)
        timer = threading.Timer(timeout, proc.kill) if timeout else None
        if timer:
            timer.start()
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.monotonic() - start
        if timer:
            timer.cancel()
    proc.returncode = os.waitstatus_to_exitcode(status)
    if timeout and wall >= timeout:
        raise CommandFailed(f"{cmd[0]} {cmd[1]} killed after {timeout} s")
    if proc.returncode != 0:
        tail = Path(log_path).read_text(errors="replace").strip().splitlines()[-3:]
        raise CommandFailed(f"{cmd[0]} {cmd[1]} failed (exit {proc.returncode}): "
                            + " | ".join(tail))
    return {"wall_s": wall, "cpu_s": usage.ru_utime + usage.ru_stime,
            "peak_mb": usage.ru_maxrss / 1024.0}


def machine_note():
    """The machine and its load when a benchmark starts (timings depend on both)."""
    load = os.getloadavg()
    return {"cores": os.cpu_count(), "load_average_1_5_15": [round(x, 2) for x in load],
            "date_utc": time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime()),
            "uname": " ".join(os.uname()[i] for i in (0, 2, 4))}


def colmap_binary():
    return shutil.which("colmap")


def colmap_version(colmap):
    try:
        out = subprocess.run([colmap, "-h"], capture_output=True, text=True, timeout=60).stdout
    except (OSError, subprocess.TimeoutExpired):
        return "unknown"
    for line in out.splitlines():
        if "COLMAP" in line:
            return line.strip()
    return "unknown"


def resolve_image_set(folder):
    """A set is a folder with images/ (and maybe gt/) or a folder of images: (images, gt)."""
    folder = Path(folder).resolve()
    if (folder / "images").is_dir():
        gt = folder / "gt" if (folder / "gt").is_dir() else None
        return folder / "images", gt
    if folder.name == "images" and (folder.parent / "gt").is_dir():
        return folder, folder.parent / "gt"
    return folder, None


def list_images(folder):
    return sorted(p for p in Path(folder).iterdir()
                  if p.suffix.lower() in IMAGE_EXTENSIONS and p.is_file())


def set_name(images_dir):
    images_dir = Path(images_dir)
    return images_dir.parent.name if images_dir.name == "images" else images_dir.name


# ---- COLMAP database (both systems write COLMAP's schema) ----

def subset_database(src, dst, keep_names):
    """Copies the database keeping only the images named in keep_names (and their pairs)."""
    shutil.copyfile(src, dst)
    db = sqlite3.connect(dst)
    keep = {row[0] for row in db.execute("SELECT image_id, name FROM images")
            if row[1] in keep_names or Path(row[1]).name in keep_names}
    drop = [row[0] for row in db.execute("SELECT image_id FROM images") if row[0] not in keep]
    for table in ("images", "keypoints", "descriptors"):
        db.executemany(f"DELETE FROM {table} WHERE image_id = ?", [(i,) for i in drop])
    for table in ("matches", "two_view_geometries"):
        pairs = [row[0] for row in db.execute(f"SELECT pair_id FROM {table}")]
        gone = [(p,) for p in pairs
                if (p // PAIR_ID_FACTOR) not in keep or (p % PAIR_ID_FACTOR) not in keep]
        db.executemany(f"DELETE FROM {table} WHERE pair_id = ?", gone)
    db.execute("DELETE FROM cameras WHERE camera_id NOT IN (SELECT camera_id FROM images)")
    db.commit()
    db.execute("VACUUM")
    db.close()
    return len(keep)


def database_stats(path):
    db = sqlite3.connect(path)
    stats = {
        "images": db.execute("SELECT COUNT(*) FROM images").fetchone()[0],
        "cameras": db.execute("SELECT COUNT(*) FROM cameras").fetchone()[0],
        "features": db.execute("SELECT COALESCE(SUM(rows), 0) FROM keypoints").fetchone()[0],
        "verified_pairs":
            db.execute("SELECT COUNT(*) FROM two_view_geometries WHERE rows > 0").fetchone()[0],
    }
    db.close()
    return stats


# ---- COLMAP text models ----

def _project(model, params, x, y, z):
    """Pixel of camera point (x, y, z) in COLMAP's camera models (those the systems write)."""
    u, v = x / z, y / z
    if model == "SIMPLE_PINHOLE":
        f, cx, cy = params
        return f * u + cx, f * v + cy
    if model == "PINHOLE":
        fx, fy, cx, cy = params
        return fx * u + cx, fy * v + cy
    if model == "SIMPLE_RADIAL":
        f, cx, cy, k = params
        d = 1 + k * (u * u + v * v)
        return f * u * d + cx, f * v * d + cy
    if model == "RADIAL":
        f, cx, cy, k1, k2 = params
        r2 = u * u + v * v
        d = 1 + k1 * r2 + k2 * r2 * r2
        return f * u * d + cx, f * v * d + cy
    if model in ("OPENCV", "FULL_OPENCV"):
        fx, fy, cx, cy, k1, k2, p1, p2 = params[:8]
        r2 = u * u + v * v
        d = 1 + k1 * r2 + k2 * r2 * r2
        if model == "FULL_OPENCV":
            k3, k4, k5, k6 = params[8:12]
            d = (1 + r2 * (k1 + r2 * (k2 + r2 * k3))) / (1 + r2 * (k4 + r2 * (k5 + r2 * k6)))
        du = 2 * p1 * u * v + p2 * (r2 + 2 * u * u)
        dv = p1 * (r2 + 2 * v * v) + 2 * p2 * u * v
        return fx * (u * d + du) + cx, fy * (v * d + dv) + cy
    raise ValueError(f"camera model {model} not supported")


def _rotate(q, p):
    w, x, y, z = q
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    px, py, pz = p
    # v' = v + 2 w (q x v) + 2 q x (q x v)
    cx, cy, cz = y * pz - z * py, z * px - x * pz, x * py - y * px
    cx2, cy2, cz2 = y * cz - z * cy, z * cx - x * cz, x * cy - y * cx
    return (px + 2 * (w * cx + cx2), py + 2 * (w * cy + cy2), pz + 2 * (w * cz + cz2))


def read_text_model(folder):
    folder = Path(folder)
    cameras, images, points = {}, {}, {}
    for line in (folder / "cameras.txt").read_text().splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        f = line.split()
        cameras[int(f[0])] = (f[1], int(f[2]), int(f[3]), [float(x) for x in f[4:]])
    lines = [l for l in (folder / "images.txt").read_text().splitlines()
             if not l.startswith("#")]
    for header, pts in zip(lines[0::2], lines[1::2]):
        f = header.split()
        if not f:
            continue
        xy = pts.split()
        obs = [(float(xy[i]), float(xy[i + 1]), int(xy[i + 2])) for i in range(0, len(xy), 3)]
        images[int(f[0])] = {"q": [float(x) for x in f[1:5]], "t": [float(x) for x in f[5:8]],
                             "camera_id": int(f[8]), "name": f[9], "obs": obs}
    for line in (folder / "points3D.txt").read_text().splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        f = line.split()
        points[int(f[0])] = (float(f[1]), float(f[2]), float(f[3]))
    return cameras, images, points


def model_stats(text_folder):
    """Registered images, points, observations, RMS and mean reprojection error (px)."""
    cameras, images, points = read_text_model(text_folder)
    sq, total, n = 0.0, 0.0, 0
    for image in images.values():
        model, _, _, params = cameras[image["camera_id"]]
        for x, y, pid in image["obs"]:
            if pid < 0 or pid not in points:
                continue
            px, py, pz = _rotate(image["q"], points[pid])
            px, py, pz = px + image["t"][0], py + image["t"][1], pz + image["t"][2]
            u, v = _project(model, params, px, py, pz)
            e2 = (u - x) ** 2 + (v - y) ** 2
            sq += e2
            total += math.sqrt(e2)
            n += 1
    return {"registered": len(images), "points3D": len(points), "observations": n,
            "rms_px": math.sqrt(sq / n) if n else None, "mean_px": total / n if n else None,
            "cameras": len(cameras)}


def colmap_best_model(colmap, sparse_dir, work):
    """COLMAP's mapper may write several models (sparse/0, 1, ...): the one with most images,
    converted to text in work/. Returns (text folder, binary folder, number of models)."""
    models = sorted(p for p in Path(sparse_dir).iterdir() if (p / "images.bin").exists()
                    or (p / "images.txt").exists()) if Path(sparse_dir).is_dir() else []
    best, best_n, best_txt = None, -1, None
    for i, m in enumerate(models):
        txt = Path(work) / f"model_txt_{m.name}"
        txt.mkdir(parents=True, exist_ok=True)
        timed([colmap, "model_converter", "--input_path", m, "--output_path", txt,
               "--output_type", "TXT"], Path(work) / f"model_converter_{m.name}.log")
        n = model_stats(txt)["registered"]
        if n > best_n:
            best, best_n, best_txt = m, n, txt
    return best_txt, best, len(models)


def evaluate(varsfm, model_dir, gt_dir, json_path, log_path):
    """`varsfm evaluate` of a COLMAP-format model against Strecha ground truth (dict or None)."""
    if gt_dir is None or model_dir is None:
        return None
    try:
        timed([varsfm, "evaluate", model_dir, "--gt", gt_dir, "--json", json_path], log_path)
    except CommandFailed as e:
        log(f"evaluate failed: {e}")
        return None
    j = json.loads(Path(json_path).read_text())
    return {"center_error_m_mean": j["center_error_m"]["mean"],
            "center_error_m_median": j["center_error_m"]["median"],
            "rotation_error_deg_mean": j["rotation_error_deg"]["mean"],
            "focal_error_percent_mean": j["focal_error_percent"]["mean"],
            "focal_error_percent_max": j["focal_error_percent"]["max"],
            "gt_images": j["num_gt_images"], "gt_registered": j["num_registered"],
            "aligned": j["aligned"]}


# ---- the two systems' stages ----

def matching_strategy(num_images):
    return "exhaustive" if num_images <= 40 else "sequential"


def varsfm_features(varsfm, images_dir, db, work, strategy, overlap=10):
    """varsfm extract + match into db; returns seconds {extract, match} and CPU seconds."""
    w_e, c_e = timed([varsfm, "extract", "--workspace", db, "--images", images_dir],
                     Path(work) / "varsfm_extract.log")
    cmd = [varsfm, "match", "--workspace", db, "--strategy", strategy]
    if strategy == "sequential":
        cmd += ["--overlap", str(overlap)]
    w_m, c_m = timed(cmd, Path(work) / "varsfm_match.log")
    return {"extract": w_e, "match": w_m}, {"extract": c_e, "match": c_m}


def varsfm_map(varsfm, db, out, images_dir, work, options=(), tag="map", timeout=None):
    """varsfm map with extra options; returns a row (stats, seconds) or raises CommandFailed."""
    if Path(out).exists():
        shutil.rmtree(out)
    wall, cpu = timed([varsfm, "map", "--workspace", db, "--output", out, "--images", images_dir,
                       *options], Path(work) / f"varsfm_{tag}.log", timeout=timeout)
    summary = json.loads((Path(out) / "summary.json").read_text())
    stats = model_stats(Path(out) / "sparse" / "0")
    return {"stats": stats, "wall_map": wall, "cpu_map": cpu,
            "summary_rms_px": summary.get("rms_reprojection_error_px"),
            "summary_seconds": summary.get("seconds", {}),
            "local_ba": summary.get("local_bundle_adjustments"),
            "global_ba": summary.get("global_bundle_adjustments")}


def colmap_features(colmap, images_dir, db, work, strategy, overlap=10, per_image_camera=False):
    """COLMAP's defaults share one camera among images of the same size and EXIF (so a zoom
    sequence without EXIF gets one focal length); per_image_camera gives each image its own."""
    extra = ["--ImageReader.single_camera_per_image", "1"] if per_image_camera else []
    w_e, c_e = timed([colmap, "feature_extractor", "--database_path", db, "--image_path",
                      images_dir, "--SiftExtraction.use_gpu", "0", *extra],
                     Path(work) / "colmap_extract.log")
    if strategy == "exhaustive":
        cmd = [colmap, "exhaustive_matcher", "--database_path", db, "--SiftMatching.use_gpu", "0"]
    else:
        cmd = [colmap, "sequential_matcher", "--database_path", db, "--SiftMatching.use_gpu", "0",
               "--SequentialMatching.overlap", str(overlap)]
    w_m, c_m = timed(cmd, Path(work) / "colmap_match.log")
    return {"extract": w_e, "match": w_m}, {"extract": c_e, "match": c_m}


def colmap_map(colmap, db, images_dir, out, work, tag="map", timeout=None):
    if Path(out).exists():
        shutil.rmtree(out)
    Path(out).mkdir(parents=True)
    wall, cpu = timed([colmap, "mapper", "--database_path", db, "--image_path", images_dir,
                       "--output_path", out], Path(work) / f"colmap_{tag}.log", timeout=timeout)
    txt, binary, n_models = colmap_best_model(colmap, out, Path(work) / f"colmap_{tag}_models")
    stats = model_stats(txt) if txt else {"registered": 0, "points3D": 0, "rms_px": None,
                                           "mean_px": None, "observations": 0, "cameras": 0}
    return {"stats": stats, "wall_map": wall, "cpu_map": cpu, "models": n_models,
            "model_dir": str(binary) if binary else None}


# ---- output ----

def fmt(v, digits=2):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    if isinstance(v, int):
        return str(v)
    return f"{v:.{digits}f}"


def markdown_table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    out += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(out)


def results_dir():
    d = ROOT / "bench" / "results"
    d.mkdir(parents=True, exist_ok=True)
    return d


def gnuplot(script, cwd):
    exe = shutil.which("gnuplot")
    if not exe:
        log("gnuplot is not installed (apt-get install -y gnuplot-nox): no plot")
        return False
    r = subprocess.run([exe], input=script, text=True, cwd=cwd, capture_output=True)
    if r.returncode != 0:
        log("gnuplot failed: " + r.stderr.strip()[-300:])
        return False
    return True


def default_varsfm():
    for p in (ROOT / "build" / "varsfm", ROOT / "build-bench" / "varsfm"):
        if p.exists():
            return p
    return ROOT / "build" / "varsfm"
