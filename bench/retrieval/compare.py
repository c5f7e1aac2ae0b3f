#!/usr/bin/env python3
"""Pair selection against exhaustive matching: recall, matching time, registered images and
accuracy, from one extraction per set.

    bench/retrieval/compare.py VARSFM WORK SET[:gt] --strategy NAME=ARGS ... [--no-map]

Per SET (a folder with images/ and, for accuracy, gt/ of Strecha cameras): `varsfm extract`
once into WORK/<set>/features.db, then for each NAME (exhaustive first: the reference) a copy
matched with `varsfm match ARGS`, mapped with `varsfm map` and evaluated with `varsfm evaluate`.
With --reference DB (one SET), DB is the exhaustively matched reference and every strategy is
measured against it. Prints one line per set and strategy: pairs matched, verified, recall against exhaustive (share
of its verified pairs, and weighted by their inliers), match seconds (wall and CPU), images
registered, camera-centre error. Run it under `nice -n 10`.
"""
import argparse
import json
import os
import shutil
import sqlite3
import subprocess
import sys
import time
from pathlib import Path


def timed(cmd, log):
    start, t0 = time.time(), os.times()
    with open(log, "w") as f:
        subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT, check=True)
    t1 = os.times()
    return time.time() - start, (t1.children_user - t0.children_user) + (
        t1.children_system - t0.children_system)


def pairs(db_path):
    db = sqlite3.connect(db_path)
    verified = dict(db.execute("SELECT pair_id, rows FROM two_view_geometries WHERE rows > 0"))
    selected = {p for (p,) in db.execute("SELECT pair_id FROM matches")}
    return verified, selected


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("varsfm")
    ap.add_argument("work")
    ap.add_argument("sets", nargs="+")
    ap.add_argument("--strategy", action="append", required=True,
                    help="NAME=match arguments, e.g. 'k20=--strategy retrieval "
                         "--retrieval-neighbors 20'; the first is the reference")
    ap.add_argument("--no-map", action="store_true")
    ap.add_argument("--reference", help="an exhaustively matched workspace of the (single) SET, "
                    "the reference instead of the first strategy")
    args = ap.parse_args()
    varsfm = str(Path(args.varsfm).resolve())
    rows = []
    for s in args.sets:
        folder = Path(s).resolve()
        images = folder / "images" if (folder / "images").is_dir() else folder
        gt = folder / "gt"
        work = Path(args.work) / folder.name
        work.mkdir(parents=True, exist_ok=True)
        features = work / "features.db"
        if not features.exists():
            timed([varsfm, "extract", "--workspace", str(features), "--images", str(images)],
                  work / "extract.log")
        reference = pairs(args.reference)[0] if args.reference else None
        for spec in args.strategy:
            name, _, match_args = spec.partition("=")
            db = work / f"{name}.db"
            shutil.copy(features, db)
            wall, cpu = timed([varsfm, "match", "--workspace", str(db)] + match_args.split(),
                              work / f"{name}-match.log")
            verified, selected = pairs(db)
            if reference is None:
                reference = verified
            total = sum(reference.values())
            found = sum(n for p, n in reference.items() if p in selected)
            row = {"set": folder.name, "strategy": name, "pairs": len(selected),
                   "verified": len(verified),
                   "recall_pairs": sum(p in selected for p in reference) / max(len(reference), 1),
                   "recall_inliers": found / max(total, 1), "match_wall_s": wall,
                   "match_cpu_s": cpu}
            if not args.no_map:
                out = work / f"{name}-model"
                shutil.rmtree(out, ignore_errors=True)
                try:
                    row["map_wall_s"], _ = timed(
                        [varsfm, "map", "--workspace", str(db), "--output", str(out)],
                        work / f"{name}-map.log")
                    models = sorted((out / "sparse").iterdir())
                    row["models"] = len(models)
                    if gt.is_dir():
                        ev = work / f"{name}-eval.json"
                        timed([varsfm, "evaluate", str(out / "sparse"), "--gt", str(gt), "--json", str(ev)],
                              work / f"{name}-eval.log")
                        e = json.loads(ev.read_text())
                        row.update({"registered": e["num_registered"],
                                    "gt_images": e["num_gt_images"],
                                    "center_error_m_mean": e["center_error_m"]["mean"],
                                    "rotation_error_deg_mean": e["rotation_error_deg"]["mean"],
                                    "focal_error_percent_mean":
                                        e["focal_error_percent"]["mean"]})
                except subprocess.CalledProcessError as e:
                    row["error"] = str(e)
            rows.append(row)
            print(json.dumps(row), flush=True)
    (Path(args.work) / "compare.json").write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    sys.exit(main())
