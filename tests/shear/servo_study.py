#!/usr/bin/env python3
"""Does the imposed-pressure servo feed its own oscillation into the stress? (issue 3 item 3)

The servo (README "Imposed pressure servo") sets L_yy = gain gd clamp((P_f - P)/P, -1, 1), P_f
the pressure low-passed over filter_strain. A servo that overshoots would make the pressure, the
cell height and L_yy oscillate at its own frequency, and would move the steady state with its
settings. The script runs one imposed-pressure spec (the physics suite's group-A delaunay spec,
N = 300, with St 0.01 also at Iv = 0.01 where the suite uses 0.1) at Iv = 1, 0.1 and 0.01 with
the default servo (gain 1, filter 0.05 strain) and with the gain and the filter changed by
factors of 4-5 each way, plus an imposed-volume run at the
default run's phi (no servo: the pressure's own fluctuations), and reports per run:
  - phi and mu with their standard errors, and their differences from the default servo in
    combined standard errors;
  - the relative pressure fluctuation std(P)/<P> of the sampled (instantaneous) pressure over
    the steady window, and its slow part (the same after a running mean over 0.2 strain);
  - the autocorrelation of P: its smallest value over lags up to 2 strain and that lag (a
    ringing loop shows a deep negative minimum at half its period), and the same for L_yy.
  - the relative fluctuation of the sampled shear stress, std(sigma_xy)/<sigma_xy>, and the
    part of it that follows phi: the slope of ln sigma_xy on phi times std(phi), and the
    correlation of phi and sigma_xy (imposed pressure: the volume is free to fluctuate).
--check exits 1 if a run's phi or mu differs from the default servo's by more than 3 combined
standard errors, or if a servo run's pressure fluctuates more (relative std) than the
imposed-volume run at the same phi. The shear stress may fluctuate more under imposed pressure
than at imposed volume: at fixed P the volume fluctuates, and where sigma_xy is steep in phi
(Iv = 1) that alone makes it larger. What a servo that feeds its own oscillation would show is
fluctuations that grow with its gain, so where a servo run's shear stress fluctuates more than
the imposed-volume run's, --check requires that the gain*4 run's shear-stress fluctuation be at
most SXY_GAIN_GROWTH times the gain/4 run's.
Writes OUT/servo_study.md, OUT/servo_study.csv and, with matplotlib, OUT/servo_study.png.
Prints name=value lines.
usage: servo_study.py --lubdem PATH --out DIR [--strain S] [--jobs J] [--reuse] [--check]
       [--iv IV [IV ...]] [--from-csv CSV]
"""
import argparse
import concurrent.futures
import csv
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "resuspension"))
from resuspension_consistency import run, summary  # noqa: E402

import run_physics  # noqa: E402  (same folder: the suite's configurations and specs)

IVS = (1.0, 0.1, 0.01)
# a loop that rings grows its fluctuations with its gain; a 16-fold gain change may leave the
# shear stress's relative fluctuation at most this factor larger (measured 0.55-1.23)
SXY_GAIN_GROWTH = 1.5
# (label, gain, filter_strain); the first is the default servo
SERVOS = (("default", 1.0, 0.05), ("gain/4", 0.25, 0.05), ("gain*4", 4.0, 0.05),
          ("filter/5", 1.0, 0.01), ("filter*5", 1.0, 0.25), ("gain*4 filter*5", 4.0, 0.25))


def tag_of(label):
    return label.replace(" ", "_").replace("/", "div").replace("*", "x")


def pressure_spec(iv, gain, filt, args):
    """the physics suite's group-A delaunay spec (run_physics.spec_for) with St 0.01 at every Iv
    (the suite uses 0.1 at Iv = 0.01), the start phi on the §2 law and the servo settings"""
    case = {"config": "delaunay", "control": "pressure", "Iv": iv, "St": 0.01,
            "strain": args.strain}
    s = run_physics.spec_for(case, 300, True)
    s.update({"seed": 1, "phi": round(0.574 / (1 + math.sqrt(iv)), 4),
              "servo": {"gain": gain, "filter_strain": filt}})
    return s


def volume_spec(iv, phi, args):
    """imposed volume at phi with the stiffness k/(eta gd a) of the pressure runs (1e4/Iv)"""
    case = {"config": "delaunay", "control": "volume", "phi": round(phi, 4),
            "strain": args.strain}
    s = run_physics.spec_for(case, 300, True)
    s.update({"seed": 1, "stiffness": 1e4 / iv})
    return s


def autocorrelation(x):
    """normalised autocorrelation of x at lags 0..len(x)-1 (FFT, zero-padded)"""
    import numpy as np
    x = np.asarray(x, float) - np.mean(x)
    n = len(x)
    f = np.fft.rfft(x, 2 * n)
    ac = np.fft.irfft(f * np.conj(f))[:n]
    return ac / ac[0]


def autocorr_min(x, max_lag):
    """smallest value of the autocorrelation over lags 1..max_lag samples (value, lag)"""
    import numpy as np
    ac = autocorrelation(x)
    m = min(max_lag, len(ac) // 2)
    k = int(np.argmin(ac[1:m + 1])) + 1
    return float(ac[k]), k


def analyse(out, iv, label, control):
    import h5py
    import numpy as np
    s = summary(out)
    r = s["results"]
    start = r["steady_from_strain"]["value"]
    with h5py.File(os.path.join(out, "result.h5"), "r") as f:
        o = f["observables"]
        g = o["strain/value"][:]
        p = o["pressure/value"][:]
        sxy = o["stress/total/value"][:, 0, 1]
        rate = o["servo_rate/value"][:] if "servo_rate" in o else None
        phi = o["phi/value"][:]
    w = g >= start
    pw = p[w]
    dg = float(np.median(np.diff(g)))
    k = max(1, int(round(0.2 / dg)))
    slow = np.convolve(pw, np.ones(k) / k, mode="valid")
    row = {"Iv": iv, "servo": label, "control": control,
           "phi": r["phi"]["value"], "phi_err": r["phi"]["stderr"],
           "mu": r["mu"]["value"], "mu_err": r["mu"]["stderr"],
           "Iv_measured": r["Iv"]["value"],
           "p_rel_std": float(np.std(pw) / np.mean(pw)),
           "p_slow_rel_std": float(np.std(slow) / np.mean(pw)),
           "sxy_rel_std": float(np.std(sxy[w]) / abs(np.mean(sxy[w]))),
           "steady_from": start, "sample_strain": dg}
    if control == "pressure" and np.std(phi[w]) > 0:
        # the part of the shear stress's fluctuation that follows phi
        slope = np.polyfit(phi[w], np.log(np.abs(sxy[w])), 1)[0]
        row["sxy_phi_part"] = float(abs(slope) * np.std(phi[w]))
        row["phi_sxy_corr"] = float(np.corrcoef(phi[w], sxy[w])[0, 1])
    else:
        row["sxy_phi_part"] = row["phi_sxy_corr"] = None
    lag2 = int(round(2.0 / dg))  # lags up to 2 strain
    m = autocorr_min(pw, lag2)
    row["p_acf_min"], row["p_acf_min_lag"] = (m[0], m[1] * dg) if m else (None, None)
    if rate is not None and control == "pressure":
        m = autocorr_min(rate[w], lag2)
        row["rate_acf_min"], row["rate_acf_min_lag"] = (m[0], m[1] * dg) if m else (None, None)
        row["rate_rms"] = float(np.sqrt(np.mean(rate[w] ** 2)))
    else:
        row["rate_acf_min"] = row["rate_acf_min_lag"] = row["rate_rms"] = None
    return row


def fmt(x, f):
    return "—" if x is None or (isinstance(x, float) and math.isnan(x)) else format(x, f)


def write_outputs(rows, out):
    keys = ["Iv", "servo", "control", "phi", "phi_err", "mu", "mu_err", "Iv_measured",
            "p_rel_std", "p_slow_rel_std", "sxy_rel_std", "sxy_phi_part", "phi_sxy_corr",
            "p_acf_min", "p_acf_min_lag", "rate_rms",
            "rate_acf_min", "rate_acf_min_lag", "steady_from", "sample_strain",
            "z_phi", "z_mu"]
    with open(os.path.join(out, "servo_study.csv"), "w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=keys, extrasaction="ignore")
        wr.writeheader()
        for r in rows:
            wr.writerow({k: r.get(k) for k in keys})
    lines = ["| Iv | servo (gain, filter) | phi | mu | z phi, z mu vs default | std(P)/<P> | "
             "slow part | std(σxy)/<σxy> | part following φ (corr) | ACF(P) min (lag, strain) | "
             "rms L_yy/gd | ACF(L_yy) min (lag) |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lab = r["servo"] if r["control"] == "pressure" else "none: imposed volume at default phi"
        z = (f"{fmt(r.get('z_phi'), '+.1f')}, {fmt(r.get('z_mu'), '+.1f')}"
             if r["control"] == "pressure" and r["servo"] != "default" else "")
        mu_txt = f"{r['mu']:.3f} ± {fmt(r['mu_err'], '.3f')}"
        phi_txt = (f"{r['phi']:.4f} ± {fmt(r['phi_err'], '.4f')}" if r["control"] == "pressure"
                   else f"{r['phi']:.4f} (Iv {r['Iv_measured']:.3g})")
        lines.append(
            f"| {r['Iv']:g} | {lab} | {phi_txt} | {mu_txt} | {z} | {r['p_rel_std']:.3f} | "
            f"{r['p_slow_rel_std']:.3f} | {fmt(r.get('sxy_rel_std'), '.3f')} | "
            f"{fmt(r.get('sxy_phi_part'), '.3f')} ({fmt(r.get('phi_sxy_corr'), '.2f')}) | "
            f"{fmt(r['p_acf_min'], '+.2f')} "
            f"({fmt(r['p_acf_min_lag'], '.2f')}) | {fmt(r['rate_rms'], '.3f')} | "
            f"{fmt(r['rate_acf_min'], '+.2f')} ({fmt(r['rate_acf_min_lag'], '.2f')}) |")
    with open(os.path.join(out, "servo_study.md"), "w") as fh:
        fh.write("\n".join(lines) + "\n")


def read_csv(path):
    rows = []
    with open(path) as fh:
        for r in csv.DictReader(fh):
            d = {}
            for k, v in r.items():
                if k in ("servo", "control"):
                    d[k] = v
                else:
                    d[k] = float(v) if v not in ("", "None") else None
            rows.append(d)
    return rows


def plot(rows, out, runs):
    try:
        import h5py
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy as np
    except ImportError:
        print("servo_study_plot=skipped (matplotlib/h5py missing)")
        return
    ivs = sorted({k[0] for k in runs}, reverse=True)
    fig, ax = plt.subplots(2, len(ivs), figsize=(5.5 * len(ivs), 7), squeeze=False)
    for col, iv in enumerate(ivs):
        for (riv, label, control), path in runs.items():
            if riv != iv:
                continue
            with h5py.File(os.path.join(path, "result.h5"), "r") as f:
                g = f["observables/strain/value"][:]
                p = f["observables/pressure/value"][:]
            p = p / np.mean(p[g >= 2.0])  # the volume runs' pressure is in eta gd
            w = (g >= 6.0) & (g <= 9.0)
            lab = label if control == "pressure" else "imposed volume"
            ax[0][col].plot(g[w], p[w], lw=0.7, label=lab)
            ac = autocorrelation(p[g >= 2.0])
            dg = float(np.median(np.diff(g)))
            m = int(1.0 / dg)
            ax[1][col].plot(np.arange(m) * dg, ac[:m], lw=0.8, label=lab)
        ax[0][col].set_title(f"Iv = {iv:g}: sampled pressure, strain 6-9")
        ax[0][col].set_xlabel("strain")
        ax[0][col].set_ylabel("-sigma_yy / <-sigma_yy>")
        ax[0][col].legend(fontsize=7)
        ax[1][col].axhline(0.0, color="k", lw=0.5)
        ax[1][col].set_xlabel("lag (strain)")
        ax[1][col].set_ylabel("autocorrelation of P")
        ax[1][col].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "servo_study.png"), dpi=110)
    print(f"plot={os.path.join(out, 'servo_study.png')}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lubdem")
    ap.add_argument("--out", required=True)
    ap.add_argument("--strain", type=float, default=12.0)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--reuse", action="store_true")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--from-csv")
    ap.add_argument("--iv", type=float, nargs="+", default=list(IVS),
                    help="the Iv values to run (default: %(default)s)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)

    runs = {}
    if a.from_csv:
        rows = read_csv(a.from_csv)
    else:
        jobs = {}
        with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as ex:
            for iv in a.iv:
                for label, gain, filt in SERVOS:
                    d = os.path.join(a.out, f"iv{iv:g}_{tag_of(label)}")
                    jobs[(iv, label, "pressure")] = ex.submit(
                        run, a.lubdem, pressure_spec(iv, gain, filt, a), d, a.reuse)
            for key, fut in jobs.items():
                runs[key] = fut.result()
        # imposed volume at the default servo's phi (needs those runs first)
        vjobs = {}
        with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as ex:
            for iv in a.iv:
                phi = summary(runs[(iv, "default", "pressure")])["results"]["phi"]["value"]
                vjobs[(iv, "none", "volume")] = ex.submit(
                    run, a.lubdem, volume_spec(iv, phi, a), os.path.join(a.out, f"iv{iv:g}_volume"),
                    a.reuse)
            for key, fut in vjobs.items():
                runs[key] = fut.result()
        rows = [analyse(path, iv, label, control) for (iv, label, control), path in runs.items()]
        rows.sort(key=lambda r: (-r["Iv"], r["control"] != "pressure",
                                 [s[0] for s in SERVOS].index(r["servo"])
                                 if r["servo"] in [s[0] for s in SERVOS] else 99))
    bad = []
    for iv in sorted({r["Iv"] for r in rows}, reverse=True):
        ref = next(r for r in rows if r["Iv"] == iv and r["servo"] == "default")
        for r in rows:
            if r["Iv"] != iv or r["control"] != "pressure":
                continue
            if r is not ref:
                for k in ("phi", "mu"):
                    e = math.hypot(r[k + "_err"] or 0.0, ref[k + "_err"] or 0.0)
                    r["z_" + k] = (r[k] - ref[k]) / e if e > 0 else float("nan")
                    if abs(r["z_" + k]) > 3:
                        bad.append(f"{k} at Iv {iv:g} with servo {r['servo']}: "
                                   f"{r['z_' + k]:+.1f} standard errors from the default servo")
        vol = next((r for r in rows if r["Iv"] == iv and r["control"] == "volume"), None)
        for r in rows:
            if r["Iv"] != iv or r["control"] != "pressure" or vol is None:
                continue
            k = "p_rel_std"
            if r.get(k) is not None and vol.get(k) is not None and r[k] > vol[k]:
                bad.append(f"pressure fluctuates more under servo {r['servo']} at Iv {iv:g} "
                           f"({r[k]:.3f}) than at imposed volume ({vol[k]:.3f})")
        # shear stress: where it fluctuates more than at imposed volume, it must not grow with
        # the gain
        over = [r for r in rows if r["Iv"] == iv and r["control"] == "pressure" and vol
                and r.get("sxy_rel_std") is not None and vol.get("sxy_rel_std") is not None
                and r["sxy_rel_std"] > vol["sxy_rel_std"]]
        lo = next((r for r in rows if r["Iv"] == iv and r["servo"] == "gain/4"), None)
        hi = next((r for r in rows if r["Iv"] == iv and r["servo"] == "gain*4"), None)
        if over and not (lo and hi):
            bad.append(f"shear stress fluctuates more under the servo than at imposed volume "
                       f"at Iv {iv:g}, and the gain/4 and gain*4 runs that would tell whether it "
                       f"grows with the gain are missing")
        elif over:
            growth = hi["sxy_rel_std"] / lo["sxy_rel_std"]
            print(f"servo_iv{iv:g}_sxy_gain_growth={growth:.4g}")
            if growth > SXY_GAIN_GROWTH:
                bad.append(f"shear stress fluctuates more under the servo than at imposed volume "
                           f"at Iv {iv:g} ({', '.join(r['servo'] for r in over)}) and grows "
                           f"with the gain: {growth:.2f} times from gain/4 to gain*4 "
                           f"(limit {SXY_GAIN_GROWTH})")
    for r in rows:
        tag = f"iv{r['Iv']:g}_{tag_of(r['servo'])}"
        if r["control"] == "volume":
            tag = f"iv{r['Iv']:g}_volume"
        for k in ("phi", "mu", "p_rel_std", "p_slow_rel_std", "sxy_rel_std", "sxy_phi_part",
                  "phi_sxy_corr", "p_acf_min",
                  "p_acf_min_lag",
                  "rate_rms", "rate_acf_min", "z_phi", "z_mu"):
            v = r.get(k)
            if v is not None:
                print(f"servo_{tag}_{k}={v:.4g}")
    write_outputs(rows, a.out)
    if runs:
        plot(rows, a.out, runs)
    if a.check:
        print(f"servo_failures={len(bad)}")
        for b in bad:
            print("FAIL " + b)
        return 1 if bad else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
