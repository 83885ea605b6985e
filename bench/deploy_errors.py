#!/usr/bin/python3
"""Errors of deployment histories against a reference history (paper sec. 5).

usage: /usr/bin/python3 bench/deploy_errors.py REFERENCE.csv RUN.csv ...

Each CSV has columns t, q1_deg, q2_deg and tip2_defl_m, one row per 1 ms (build/deploy
--csv, build/segmented, build/peer_mujoco --csv). For each run it prints:
  dq1, dq2  max |q - q_ref| (deg) for t < 2.9939 s (the rigid model's joint 2 lock minus
            10 ms, as BENCHMARKS.md section 2), the run interpolated to the reference's times
  freq      link 2's tip vibration frequency from the zero crossings of the deflection
            minus its mean, between joint 2's lock and joint 1's (3.05-3.95 s) and after
            both (4.5-6 s), relative to the reference's
Frequencies do not depend on whether the deflection is measured from the chord or the
tangent at the root; amplitudes do (BENCHMARKS.md), so none are compared here.
Needs numpy (Debian: python3-numpy).
"""
import sys
import numpy as np

T_PRE = 2.9939
WINDOWS = ((3.05, 3.95), (4.5, 6.0))


def load(path):
    return np.genfromtxt(path, delimiter=",", names=True)


def frequency(t, y, window):
    """Mean frequency from the zero crossings of y minus its mean over the window."""
    inside = (t >= window[0]) & (t <= window[1])
    tt = t[inside]
    yy = y[inside] - y[inside].mean()
    sign = np.sign(yy)
    i = np.where(sign[:-1] * sign[1:] < 0)[0]
    crossings = tt[i] - yy[i] * (tt[i + 1] - tt[i]) / (yy[i + 1] - yy[i])
    return (len(crossings) - 1) / 2 / (crossings[-1] - crossings[0])


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    ref = load(sys.argv[1])
    pre = ref["t"] < T_PRE
    ref_freq = [frequency(ref["t"], ref["tip2_defl_m"], w) for w in WINDOWS]
    print("reference %s: frequency %.4f Hz (3.05-3.95 s), %.4f Hz (4.5-6 s)"
          % (sys.argv[1], ref_freq[0], ref_freq[1]))
    for path in sys.argv[2:]:
        run = load(path)
        errs = []
        for col in ("q1_deg", "q2_deg"):
            q = np.interp(ref["t"][pre], run["t"], run[col])
            errs.append(np.abs(q - ref[col][pre]).max())
        freq = [frequency(run["t"], run["tip2_defl_m"], w) for w in WINDOWS]
        rel = [100 * (f / r - 1) for f, r in zip(freq, ref_freq)]
        print("%-28s dq1 %.4f dq2 %.4f deg  freq %+.2f %% / %+.2f %%"
              % (path, errs[0], errs[1], rel[0], rel[1]))


if __name__ == "__main__":
    main()
