#!/usr/bin/python3
"""Bjøntegaard delta rate and delta PSNR between two rate-distortion curves.

G. Bjøntegaard, "Calculation of average PSNR differences between RD-curves",
VCEG-M33 (2001): fit each curve's log(rate) as a function of PSNR, average the
gap between the two fits over the PSNR interval both curves cover, and report
exp(gap) - 1. BD-PSNR swaps the axes: the average PSNR gap over the log-rate
interval both curves cover.

The fit here is the piecewise cubic Hermite interpolant with Fritsch-Carlson
monotone slopes (PCHIP, as scipy.interpolate.PchipInterpolator computes them),
integrated exactly. VCEG-M33's single cubic polynomial overshoots between
unevenly spaced points and extrapolates wildly at the ends of a curve; the
piecewise form passes through every point and is monotone wherever the data
are, which is why current tools (JVET's CTC spreadsheet, AOM's libaom
scripts, the `bjontegaard` Python package's default) moved to it. Plain
Python, no numpy.

Each curve is first reduced to its Pareto front (no other point of the same
curve is both smaller and better): a codec's operating points that are
beaten by its own other settings are not part of what it offers. A point
that costs more than the front's last for less than MIN_PSNR_STEP_DB more
quality is beaten too: no measure here resolves that step, and a knot that
close makes the fit jump there and carry the jump to the next point (the
Duck at 2026-12 had a 27,228 B file 0.005 dB above a 23,872 B one, which
moved its BD-rate from -4% to -1%).

Sign: bd_rate(anchor, test) < 0 means the test curve is smaller at equal
quality (-0.2: 20% fewer bytes).
"""
import math

MIN_OVERLAP_DB = 1.0  # a PSNR overlap narrower than this gives no BD-rate (see bd_rate)
MIN_PSNR_STEP_DB = 0.05  # a costlier point must be this much better to join the front


def pareto_front(points):
    """(rate, psnr) pairs -> the non-dominated ones, by increasing rate (and PSNR)."""
    out = []
    for rate, psnr in sorted(points, key=lambda p: (p[0], -p[1])):
        if rate > 0 and math.isfinite(psnr) and (not out or psnr > out[-1][1] + MIN_PSNR_STEP_DB):
            out.append((rate, psnr))
    return out


def widest_front_gap(points):
    """(low, high) PSNR of the two neighbours on the Pareto front farthest apart in PSNR, or None with fewer
    than two front points. Between them the curve has no file: a fit there (and a BD-rate that integrates over
    it) reads the interpolation, not something a user can have."""
    front = pareto_front(points)
    gaps = [(b[1] - a[1], a[1], b[1]) for a, b in zip(front, front[1:])]
    if not gaps:
        return None
    _, low, high = max(gaps)
    return (low, high)


def _slopes(x, y):
    """Fritsch-Carlson derivatives at the knots (scipy's PCHIP rule)."""
    n = len(x)
    h = [x[k + 1] - x[k] for k in range(n - 1)]
    m = [(y[k + 1] - y[k]) / h[k] for k in range(n - 1)]
    if n == 2:
        return [m[0], m[0]]
    d = [0.0] * n
    for k in range(1, n - 1):
        if m[k - 1] * m[k] <= 0:
            d[k] = 0.0
        else:
            w1, w2 = 2 * h[k] + h[k - 1], h[k] + 2 * h[k - 1]
            d[k] = (w1 + w2) / (w1 / m[k - 1] + w2 / m[k])

    def end(h0, h1, m0, m1):
        e = ((2 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
        if e * m0 <= 0:
            return 0.0
        if m0 * m1 <= 0 and abs(e) > 3 * abs(m0):
            return 3 * m0
        return e

    d[0] = end(h[0], h[1], m[0], m[1])
    d[-1] = end(h[-1], h[-2], m[-1], m[-2])
    return d


def pchip_integral(x, y, lo, hi):
    """Exact integral over [lo, hi] (inside [x[0], x[-1]]) of the PCHIP through (x, y)."""
    d = _slopes(x, y)

    def antiderivative(s, y0, y1, d0, d1, h):  # of the Hermite cubic on one segment, s in [0, 1]
        s2, s3, s4 = s * s, s ** 3, s ** 4
        return h * (y0 * (s4 / 2 - s3 + s) + h * d0 * (s4 / 4 - 2 * s3 / 3 + s2 / 2) +
                    y1 * (-s4 / 2 + s3) + h * d1 * (s4 / 4 - s3 / 3))

    total = 0.0
    for k in range(len(x) - 1):
        a, b = max(lo, x[k]), min(hi, x[k + 1])
        if b <= a:
            continue
        h = x[k + 1] - x[k]
        args = (y[k], y[k + 1], d[k], d[k + 1], h)
        total += antiderivative((b - x[k]) / h, *args) - antiderivative((a - x[k]) / h, *args)
    return total


def _average_gap(anchor, test, min_overlap):
    """anchor, test: (x, y) knots with increasing x. Mean of test - anchor over the common x
    interval, and that interval; gap None when the interval is narrower than min_overlap."""
    lo = max(anchor[0][0], test[0][0])
    hi = min(anchor[0][-1], test[0][-1])
    if hi - lo < min_overlap or hi <= lo:
        return None, (lo, hi)
    gap = (pchip_integral(*test, lo, hi) - pchip_integral(*anchor, lo, hi)) / (hi - lo)
    return gap, (lo, hi)


def bd_rate(anchor, test, min_overlap_db=MIN_OVERLAP_DB):
    """anchor, test: lists of (bytes, psnr). Returns a dict:
      bd_rate    test bytes / anchor bytes - 1 at equal PSNR, averaged in log over the overlap
                 (None when either front has < 2 points or the overlap is < min_overlap_db)
      overlap    (lo, hi) dB both fronts cover (lo > hi: none)
      ceiling_anchor, ceiling_test   highest PSNR of each curve
      points_anchor, points_test     points on each Pareto front
      why        why bd_rate is None ('' otherwise)
    """
    fa, ft = pareto_front(anchor), pareto_front(test)
    r = {"bd_rate": None, "overlap": None, "ceiling_anchor": max((p for _, p in fa), default=None),
         "ceiling_test": max((p for _, p in ft), default=None), "points_anchor": len(fa),
         "points_test": len(ft), "why": ""}
    if len(fa) < 2 or len(ft) < 2:
        r["why"] = "fewer than 2 points on a curve"
        return r
    knots = lambda f: ([p for _, p in f], [math.log(b) for b, _ in f])
    gap, r["overlap"] = _average_gap(knots(fa), knots(ft), min_overlap_db)
    if gap is None:
        lo, hi = r["overlap"]
        r["why"] = ("no PSNR overlap" if hi <= lo else f"PSNR overlap only {hi - lo:.2f} dB")
        return r
    r["bd_rate"] = math.exp(gap) - 1
    return r


def bd_psnr(anchor, test, min_overlap_log=0.0):
    """Mean PSNR of test minus anchor (dB) over the log-rate interval both Pareto fronts cover;
    None when they share no rate interval."""
    fa, ft = pareto_front(anchor), pareto_front(test)
    if len(fa) < 2 or len(ft) < 2:
        return None
    knots = lambda f: ([math.log(b) for b, _ in f], [p for _, p in f])
    gap, _ = _average_gap(knots(fa), knots(ft), max(min_overlap_log, 1e-12))
    return gap


def next_file_up_rate(anchor, test, min_overlap_db=MIN_OVERLAP_DB):
    """Rate ratio with no fit: for each quality q over the interval both Pareto fronts span, each curve
    offers its smallest file of q dB or better (its next front point up); returns exp(mean over q of
    ln(test bytes / anchor bytes)) - 1, exactly, since both costs are step functions of q. None when either
    front is empty or the interval is narrower than min_overlap_db.

    Where a front has a wide gap, BD-rate compares a smooth fit across it with the other curve; here the
    curve pays for its next real file across the gap, as a user who asks for that quality does."""
    fa, ft = pareto_front(anchor), pareto_front(test)
    if not fa or not ft:
        return None
    lo, hi = max(fa[0][1], ft[0][1]), min(fa[-1][1], ft[-1][1])
    if hi - lo < min_overlap_db:
        return None
    def cost(front, q):  # the first front point at q dB or better (fronts rise in bytes and PSNR)
        return next(b for b, p in front if p >= q)
    cuts = sorted({lo, hi} | {p for _, p in fa + ft if lo < p < hi})
    total = 0.0
    for a, b in zip(cuts, cuts[1:]):  # both costs are constant on (a, b]
        total += (b - a) * (math.log(cost(ft, b)) - math.log(cost(fa, b)))
    return math.exp(total / (hi - lo)) - 1


def geometric_mean_ratio(bd_rates):
    """Geometric mean of (1 + BD-rate) over the given values (None skipped), minus 1."""
    v = [1 + b for b in bd_rates if b is not None]
    if not v:
        return None
    return math.exp(sum(math.log(x) for x in v) / len(v)) - 1
