#!/usr/bin/env python3
"""Recall of a pair selection against exhaustive matching, from two workspaces.

    recall.py EXHAUSTIVE.db OTHER.db

EXHAUSTIVE.db was matched with --strategy exhaustive, OTHER.db with the strategy measured (from
the same features). Prints the share of exhaustively verified pairs that OTHER selected, counted
by pairs and weighted by their inliers (issue 21's recall), and the pairs each matched.
"""
import sqlite3
import sys


def verified(path):
    db = sqlite3.connect(path)
    rows = dict(db.execute("SELECT pair_id, rows FROM two_view_geometries WHERE rows > 0"))
    selected = {pair for (pair,) in db.execute("SELECT pair_id FROM matches")}
    return rows, selected


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    truth, truth_selected = verified(sys.argv[1])
    other, other_selected = verified(sys.argv[2])
    total = sum(truth.values())
    found = sum(n for pair, n in truth.items() if pair in other_selected)
    pairs_found = sum(1 for pair in truth if pair in other_selected)
    print(f"pairs matched: exhaustive {len(truth_selected)}, other {len(other_selected)}")
    print(f"verified pairs: exhaustive {len(truth)}, other {len(other)}")
    print(f"recall by pairs {pairs_found / max(len(truth), 1):.4f}, "
          f"weighted by inliers {found / max(total, 1):.4f}")


if __name__ == "__main__":
    main()
