#!/usr/bin/python3
"""Unit tests of benchmarks/bdrate.py on synthetic curves with known answers (run by ctest)."""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bdrate  # noqa: E402

# A plausible codec curve: unevenly spaced, PSNR concave in log-rate.
A = [(12_000, 31.0), (18_500, 34.2), (26_000, 36.9), (41_000, 39.8), (70_000, 42.5), (150_000, 46.0)]


class BdRate(unittest.TestCase):
    def test_widest_front_gap_is_between_front_neighbours(self):
        # (30_000, 35.0) is beaten by (26_000, 36.9): not on the front, so it cannot close a gap.
        self.assertEqual(bdrate.widest_front_gap(A + [(30_000, 35.0)]), (42.5, 46.0))
        self.assertEqual(bdrate.widest_front_gap(A + [(300_000, 60.0)]), (46.0, 60.0))
        self.assertIsNone(bdrate.widest_front_gap(A[:1]))

    def test_every_rate_times_0_8_is_minus_20_percent(self):
        b = [(r * 0.8, p) for r, p in A]
        res = bdrate.bd_rate(A, b)
        self.assertAlmostEqual(res["bd_rate"], -0.2, places=12)
        self.assertEqual(res["overlap"], (31.0, 46.0))
        self.assertAlmostEqual(bdrate.bd_rate(b, A)["bd_rate"], 0.25, places=12)

    def test_shifted_psnr_gives_bd_psnr(self):
        b = [(r, p + 1.5) for r, p in A]
        self.assertAlmostEqual(bdrate.bd_psnr(A, b), 1.5, places=12)
        self.assertAlmostEqual(bdrate.bd_psnr(b, A), -1.5, places=12)
        res = bdrate.bd_rate(A, b)
        self.assertLess(res["bd_rate"], 0)  # better quality at equal bytes: fewer bytes at equal quality
        self.assertEqual(res["ceiling_test"], 47.5)
        self.assertEqual(res["overlap"], (32.5, 46.0))

    def test_linear_log_rate_integrates_exactly(self):
        # log(rate) linear in PSNR on both curves: the fit is exact, the gap known in closed form.
        # anchor: ln r = 0.2 p; test: ln r = 0.2 p - 0.1 (p - 30); over [30, 40] the mean gap is -0.5.
        anchor = [(math.exp(0.2 * p), p) for p in (30, 32, 35, 37, 40)]
        test = [(math.exp(0.2 * p - 0.1 * (p - 30)), p) for p in (30, 31, 34, 38, 40)]
        self.assertAlmostEqual(bdrate.bd_rate(anchor, test)["bd_rate"], math.exp(-0.5) - 1, places=12)

    def test_pchip_reproduces_a_monotone_cubic_closely(self):
        x = [0, 0.5, 1.2, 2, 3]
        y = [v ** 3 + v for v in x]
        exact = 3 ** 4 / 4 + 3 ** 2 / 2
        self.assertAlmostEqual(bdrate.pchip_integral(x, y, 0, 3), exact, delta=0.02 * exact)

    def test_small_overlap_gives_no_number(self):
        b = [(r, p + 14.5) for r, p in A]  # overlap 45.5..46: 0.5 dB
        res = bdrate.bd_rate(A, b)
        self.assertIsNone(res["bd_rate"])
        self.assertIn("0.50 dB", res["why"])
        c = [(r, p + 20) for r, p in A]
        self.assertEqual(bdrate.bd_rate(A, c)["why"], "no PSNR overlap")

    def test_dominated_points_leave_the_front(self):
        pts = A + [(80_000, 40.0), (13_000, 30.0)]  # each beaten by a point of A
        self.assertEqual(bdrate.pareto_front(pts), sorted(A))
        self.assertAlmostEqual(bdrate.bd_rate(pts, [(r * 0.8, p) for r, p in A])["bd_rate"], -0.2, places=12)

    def test_a_costlier_point_hardly_better_leaves_the_front(self):
        # 30% more bytes for 0.01 dB: not a quality level of its own, so the
        # curve and its BD-rate stay those of A.
        pts = A + [(26_000 * 1.3, 36.91)]
        self.assertEqual(bdrate.pareto_front(pts), sorted(A))
        self.assertAlmostEqual(bdrate.bd_rate(pts, [(r * 0.8, p) for r, p in A])["bd_rate"], -0.2, places=12)
        # 0.1 dB better is a step the front keeps.
        self.assertIn((26_000 * 1.3, 37.0), bdrate.pareto_front(A + [(26_000 * 1.3, 37.0)]))

    def test_next_file_up_pays_for_the_next_real_file(self):
        # Over (30, 35] the test's 150 B file against the anchor's 200 B one, over (35, 40] its
        # 400 B file against 200 B: the mean log ratio is (ln 0.75 + ln 2) / 2.
        anchor = [(100, 30.0), (200, 40.0)]
        test = [(100, 30.0), (150, 35.0), (400, 40.0)]
        self.assertAlmostEqual(bdrate.next_file_up_rate(anchor, test), math.sqrt(1.5) - 1, places=12)

    def test_next_file_up_matches_bd_rate_on_a_uniform_saving(self):
        b = [(r * 0.8, p) for r, p in A]
        self.assertAlmostEqual(bdrate.next_file_up_rate(A, b), -0.2, places=12)
        self.assertAlmostEqual(bdrate.next_file_up_rate(b, A), 0.25, places=12)

    def test_next_file_up_does_not_reward_a_gap(self):
        # The test curve drops its middle points: BD-rate's fit glides across the gap (close to
        # the anchor there), but a user asking for 36 dB gets the test's 150,000 B file.
        test = [A[0], A[-1]]
        step = bdrate.next_file_up_rate(A, test)
        fit = bdrate.bd_rate(A, test)["bd_rate"]
        self.assertGreater(step, fit + 0.5)
        # Between 31 and 46 dB the anchor's own cost: known, file by file.
        cuts = [31.0, 34.2, 36.9, 39.8, 42.5, 46.0]
        anchor_costs = [18_500, 26_000, 41_000, 70_000, 150_000]
        mean = sum((b - a) * math.log(150_000 / c) for a, b, c in zip(cuts, cuts[1:], anchor_costs)) / 15.0
        self.assertAlmostEqual(step, math.exp(mean) - 1, places=12)

    def test_next_file_up_needs_an_overlap(self):
        self.assertIsNone(bdrate.next_file_up_rate(A, [(r, p + 14.5) for r, p in A]))
        self.assertIsNone(bdrate.next_file_up_rate(A, []))

    def test_geometric_mean(self):
        self.assertAlmostEqual(bdrate.geometric_mean_ratio([-0.2, 0.25, None]), 0.0, places=12)
        self.assertIsNone(bdrate.geometric_mean_ratio([None]))


if __name__ == "__main__":
    unittest.main()
