"""Analysis for bench_speed_vs_error.py: each strategy's non-dominated settings,
log-log interpolation at common times and errors, convergence slopes, and the
sentences saying where a strategy loses."""
from __future__ import annotations

import re

import numpy as np


def ms(t):
    return f"{t * 1e3:.3g} ms"


def param(label):
    return "d" if "depth d" in label else "k" if re.search(r"\bk\b", label) else "n"


def groups(rows):
    out = {}
    for r in rows:
        out.setdefault(r["strategy"], []).append(r)
    return out


def front(rs, extend=False):
    """Log (time, RMSE) of the settings not beaten by a faster one (what a user would pick). With
    extend, the last error is held up to the slowest setting measured: if a strategy's slowest
    settings are worse than a faster one, more time buys nothing and the error stays at its floor."""
    pts = []
    for t, e in sorted((r["time"], r["rmse"]) for r in rs):
        if not pts or e < pts[-1][1]:
            pts.append((t, e))
    t_max = max(r["time"] for r in rs)
    if extend and t_max > pts[-1][0]:
        pts.append((t_max, pts[-1][1]))
    return np.log(np.array(pts))


def err_at(fr, t):
    lt = np.log(t)
    return None if len(fr) < 2 or not fr[0, 0] <= lt <= fr[-1, 0] else float(np.exp(np.interp(lt, fr[:, 0], fr[:, 1])))


def time_at(fr, e):
    le = np.log(e)
    return None if len(fr) < 2 or not fr[-1, 1] <= le <= fr[0, 1] else \
        float(np.exp(np.interp(le, fr[::-1, 1], fr[::-1, 0])))


def slope(xs, ys):
    return float(np.polyfit(np.log(xs), np.log(ys), 1)[0]) if len(xs) >= 3 else None


def ratio_cell(v, base, fmt):
    return "-" if v is None or base is None else f"{fmt(v)} ({v / base:.2f}x)"


def compare(rows, baseline):
    """Slopes, and errors at three common times / times at three common errors."""
    g = groups(rows)
    fb = front(g[baseline])
    times = np.exp(np.linspace(fb[0, 0], fb[-1, 0], 5)[1:4])
    errs = np.exp(np.linspace(fb[0, 1], fb[-1, 1], 5)[1:4])
    out = {}
    for label, rs in g.items():
        fr, fx = front(rs), front(rs, extend=True)
        out[label] = dict(
            slope_t=slope([r["time"] for r in rs], [r["rmse"] for r in rs]),
            slope_r=slope([r["rays"] for r in rs], [r["rmse"] for r in rs]),
            e=[err_at(fx, t) for t in times], t=[time_at(fr, e) for e in errs],
            ns=max(rs, key=lambda r: r["time"])["ns_per_ray"], single=len(rs) == 1,
            at=err_at(fb, rs[0]["time"]) if len(rs) == 1 else None)
    return times, errs, out


def losses(rows, cmp, times, baseline):
    """Sentences on where each strategy loses, read off the numbers."""
    rows_err, g = {r["strategy"]: r["rmse"] for r in rows}, groups(rows)
    base = cmp[baseline]
    lines = []
    for label, c in cmp.items():
        said = []
        pairs = [(t, e / b) for t, e, b in zip(times, c["e"], base["e"]) if e is not None and b is not None]
        if label != baseline and pairs:
            lose = [f"{ms(t)} ({q:.2f}x)" for t, q in pairs if q > 1.05]
            win = [f"{ms(t)} ({q:.2f}x)" for t, q in pairs if q < 0.95]
            if lose:
                said.append(f"loses to {baseline} at equal time: error ratio at " + ", ".join(lose))
            if win:
                said.append("wins at " + ", ".join(win))
        elif c["single"]:
            said.append("(one setting) is outside the time range of " + baseline if c["at"] is None else
                        f"(one setting) has {rows_err[label] / c['at']:.2f}x the error of {baseline} at its time")
        elif label != baseline:
            said.append(f"has no time in common with {baseline} (see the plot)")
        rs = g[label]
        best = min(rs, key=lambda r: r["rmse"])
        worse = [r for r in rs if r["time"] > best["time"]]
        if c["slope_r"] is not None and c["slope_r"] > -0.3:
            said.append(f"barely converges (slope {c['slope_r']:.2f} against rays): an error floor")
        elif worse:
            said.append(f"stops improving: its best RMSE is {best['rmse']:.4f} at {param(label)}={best['n']}, and "
                        + ", ".join(f"{param(label)}={r['n']} ({r['rmse']:.4f})" for r in worse) + " is worse")
        if not c["single"] and c["ns"] > 1.3 * base["ns"]:
            said.append(f"costs {c['ns'] / base['ns']:.1f}x the time per ray of {baseline} "
                        "(largest settings)")
        if said:
            lines.append(f"- **{label}** " + "; ".join(said) + ".")
    return lines


def adaptive_verdict(name, rows, cmp, baseline):
    """Does any adaptive setting beat uniform jittering at equal time? Checked at 7 times over the overlap."""
    g = groups(rows)
    fb = front(g[baseline], extend=True)
    lines = []
    for label in (k for k in g if k.startswith("adaptive")):
        fa = front(g[label], extend=True)
        lo, hi = max(fa[0, 0], fb[0, 0]), min(fa[-1, 0], fb[-1, 0])
        if len(fa) < 2 or lo >= hi:
            lines.append(f"- {name}, {label}: no time in common with {baseline}.")
            continue
        ts = np.exp(np.linspace(lo, hi, 7))
        q = [err_at(fa, t) / err_at(fb, t) for t in ts]
        wins = [f"{ms(t)}: {x:.2f}x" for t, x in zip(ts, q)]
        verdict = "beats" if max(q) < 1 else "loses to" if min(q) > 1 else "beats only part of the time"
        best = min(g[label], key=lambda r: r["rmse"])
        reach = time_at(front(g[baseline]), best["rmse"])
        lines.append(f"- {name}, {label} **{verdict}** {baseline} at equal time (adaptive/jittered RMSE: "
                     + ", ".join(wins) + f"). Adaptive's lowest RMSE is {best['rmse']:.4f} (d={best['n']}, "
                     f"{ms(best['time'])}); " + (f"{baseline} reaches it in {ms(reach)} and goes on to "
                     if reach else f"{baseline} goes down to ") + f"{min(r['rmse'] for r in g[baseline]):.4f}.")
    return lines
