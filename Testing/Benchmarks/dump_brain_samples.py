#!/usr/bin/python3
"""Writes the real brain feature sets that BenchmarkLibraries reads (float32, row-major):
the same 6D / 24D features and the same N distinct rows per size as compare_sklearn.py
(distinct_sample(X, N, seed=N)), plus a seeded uniform draw of voxels as out-of-sample
queries.

  /usr/bin/python3 Testing/Benchmarks/dump_brain_samples.py --out /tmp/mcv_libbench
writes <out>/{6D,24D}_N{2000,5000,10000}.f32 and <out>/{6D,24D}_voxels.f32 (--voxels rows).
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare_sklearn import REPO, brain_features, distinct_sample  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--volumes", default=os.path.join(REPO, ".cache", "volumes"))
    ap.add_argument("--out", default="/tmp/mcv_libbench")
    ap.add_argument("--sizes", default="2000,5000,10000")
    ap.add_argument("--voxels", type=int, default=200000)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    feats, _shape = brain_features(args.volumes)
    for fs, X in feats.items():
        for n in [int(s) for s in args.sizes.split(",")]:
            np.ascontiguousarray(distinct_sample(X, n, seed=n), dtype=np.float32).tofile(
                os.path.join(args.out, f"{fs}_N{n}.f32"))
        rows = np.random.default_rng(7).choice(X.shape[0], size=min(args.voxels, X.shape[0]), replace=False)
        np.ascontiguousarray(X[rows], dtype=np.float32).tofile(os.path.join(args.out, f"{fs}_voxels.f32"))
        print(f"{fs}: {X.shape[0]} voxels, wrote samples and {rows.size} query voxels to {args.out}")


if __name__ == "__main__":
    main()
