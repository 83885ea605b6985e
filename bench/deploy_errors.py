#!/usr/bin/python3
"""Errors of deployment histories against a reference history (paper sec. 5).

usage: /usr/bin/python3 bench/deploy_errors.py REFERENCE.csv RUN.csv ...

Each CSV has columns t, q1_deg, q2_deg and tip2_defl_m, one row per 1 ms (build/deploy
--csv, build/segmented, build/peer_mujoco --csv). For each run it prints:
  dq1, dq2  max |q - q_ref| (deg) for t < 2.9939 s (the rigid model's joint 2 lock minus
            10 ms, as BENCHMARKS.md section 2), the run interpolated to the reference's times
  freq      link 2's tip vibration frequency (the dominant one, fitted by least squares),
            between joint 2's lock and joint 1's (3.05-3.95 s) and after
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


def fit_residual(tt, yy, freqs):
    """Least-squares residual of yy against a constant, a ramp and a sine pair per
    frequency."""
    cols = [np.ones_like(tt), tt - tt.mean()]
    for f in freqs:
        cols += [np.cos(2 * np.pi * f * tt), np.sin(2 * np.pi * f * tt)]
    a = np.column_stack(cols)
    coef = np.linalg.lstsq(a, yy, rcond=None)[0]
    return np.sum((yy - a @ coef) ** 2)


def spectrum_peaks(tt, yy):
    """Frequencies of the periodogram's local maxima above 5 % of the largest, the
    largest first (Hann window, zero-padded to 2^16 points)."""
    n = 1 << 16
    mag = np.abs(np.fft.rfft((yy - yy.mean()) * np.hanning(len(yy)), n))
    f = np.fft.rfftfreq(n, tt[1] - tt[0])
    peaks = [i for i in range(1, len(mag) - 1)
             if mag[i] > mag[i - 1] and mag[i] >= mag[i + 1] and mag[i] > 0.05 * mag.max()]
    peaks.sort(key=lambda i: -mag[i])
    return [f[i] for i in peaks]


def frequency(t, y, window):
    """The dominant frequency of y over the window: the periodogram's largest peak,
    refined by least squares (golden-section search on the frequency) with the other
    peaks' sine pairs, a constant and a ramp fitted alongside. Zero crossings, used
    before, move by up to 0.5 % with a 6 % ripple of a 13 Hz mode."""
    tt = np.arange(window[0], window[1], 1e-3)   # a uniform grid: rows follow the steps
    yy = np.interp(tt, t, y)
    peaks = spectrum_peaks(tt, yy)
    main, others = peaks[0], peaks[1:4]
    lo, hi = 0.9 * main, 1.1 * main
    g = (np.sqrt(5) - 1) / 2
    for _ in range(60):
        a = hi - g * (hi - lo)
        b = lo + g * (hi - lo)
        if fit_residual(tt, yy, [a] + others) < fit_residual(tt, yy, [b] + others):
            hi = b
        else:
            lo = a
    return 0.5 * (lo + hi)


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
