#!/usr/bin/env python3
"""Throughput of two shear_bench binaries compared on a noisy shared host (issue 3, "Speed").

The host's speed drifts by tens of per cent between minutes, so two binaries run one after the
other cannot be compared by their single figures. This script runs them in ABBA blocks (A, B, B,
A, back to back), so that a linear drift and the first/second position cancel inside each
block, and reports the median over blocks of B/A = (B1 + B2)/(A1 + A2) of the
particle-steps/s printed by shear_bench, with a bootstrap 90 % interval of that median.

Running the same binary as A and B gives the null result to expect (about 1.00 within a few per
cent). The two binaries must be built the same way (build type, LTO, SIMD) and should come from
the same source tree path, or at least both from fresh builds.

The same binary as A and B with --threads-b 2 measures the speed-up of 2 threads over 1 the
same way.

usage: shear_bench_compare.py A B [--blocks K] [--n N] [--steps S] [--threads T]
                              [--threads-b TB]
prints name=value lines: compare_blocks, compare_ratio_median, compare_ratio_ci90_low/high,
compare_a_median, compare_b_median (particle-steps/s).
"""
import argparse
import math
import random
import statistics
import subprocess
import sys


def throughput(binary, n, threads, steps):
    out = subprocess.run([binary, str(n), str(threads), str(steps)], capture_output=True,
                         text=True, check=True).stdout
    for line in out.splitlines():
        if line.startswith("shear_particle_steps_per_s="):
            return float(line.split("=", 1)[1])
    sys.exit(f"{binary}: no shear_particle_steps_per_s line")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--blocks", type=int, default=20)
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--steps", type=int, default=600)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--threads-b", type=int, default=0, help="threads of B (default: --threads)")
    args = ap.parse_args()
    tb = args.threads_b if args.threads_b > 0 else args.threads
    logs, va, vb = [], [], []
    for _ in range(args.blocks):
        a1 = throughput(args.a, args.n, args.threads, args.steps)
        b1 = throughput(args.b, args.n, tb, args.steps)
        b2 = throughput(args.b, args.n, tb, args.steps)
        a2 = throughput(args.a, args.n, args.threads, args.steps)
        logs.append(math.log((b1 + b2) / (a1 + a2)))
        va += [a1, a2]
        vb += [b1, b2]
    rng = random.Random(1)
    boots = sorted(statistics.median(rng.choices(logs, k=len(logs))) for _ in range(2000))
    print(f"compare_n={args.n}")
    print(f"compare_threads={args.threads}")
    print(f"compare_threads_b={tb}")
    print(f"compare_blocks={args.blocks}")
    print(f"compare_ratio_median={math.exp(statistics.median(logs)):.4f}")
    print(f"compare_ratio_ci90_low={math.exp(boots[len(boots) // 20]):.4f}")
    print(f"compare_ratio_ci90_high={math.exp(boots[len(boots) - 1 - len(boots) // 20]):.4f}")
    print(f"compare_a_median={statistics.median(va):.4g}")
    print(f"compare_b_median={statistics.median(vb):.4g}")


if __name__ == "__main__":
    main()
