"""Time the closure solve for c_sd on a 200 x 200 (ft, w) grid (target < 0.2 s).

Run: python benchmarks/analytical.py
"""

import time

import numpy as np

import core


def main(n: int = 200, repeats: int = 7) -> None:
    ft, w = np.meshgrid(np.linspace(0.0, 0.999, n), np.linspace(0.0, 0.999, n))
    core.shakedown_stick_halfwidth(ft, w)  # warm-up (imports, first call)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        c = core.shakedown_stick_halfwidth(ft, w)
        times.append(time.perf_counter() - t0)
    inside = int(np.count_nonzero(~np.isnan(c)))
    print(f"c_sd on a {n} x {n} grid ({inside} points in the shakedown region): "
          f"best {min(times) * 1e3:.1f} ms, median {np.median(times) * 1e3:.1f} ms over {repeats} runs (target < 200 ms)")
    t0 = time.perf_counter()
    core.w_limit(np.linspace(0, 1, n * n))
    print(f"w_limit on {n * n} points: {(time.perf_counter() - t0) * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
