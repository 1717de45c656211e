#!/usr/bin/python3
"""Unit test of report.rate_control_speed on hand-made bench rows (run by ctest)."""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import report  # noqa: E402


def point(setting, seconds, curve="ours"):
    return {"curve": curve, "setting": setting, "bytes": 1, "psnr": 40.0, "encode_s": seconds}


class RateControlSpeed(unittest.TestCase):
    def test_ratios_to_the_default_encode_in_target_order(self):
        rows = [{"model": "Truck", "encode_s": 20.0,
                 "rd": [point("jpeg target 44", 90.0), point("jpeg target 40", 50.0), point("default", 20.0),
                        point("jpeg q50", 9.0, curve="b1")]},
                {"model": "Plane", "encode_s": 2.0, "rd": [point("jpeg target 40", 3.0)]},
                {"model": "Untextured", "encode_s": 1.0, "rd": []}]
        lines = report.rate_control_speed(rows)
        header = next(l for l in lines if l.startswith("| model"))
        self.assertLess(header.index("jpeg target 40"), header.index("jpeg target 44"))
        truck = next(l for l in lines if l.startswith("| Truck"))
        self.assertIn("50.0 (2.5x)", truck)
        self.assertIn("90.0 (4.5x)", truck)
        plane = next(l for l in lines if l.startswith("| Plane"))
        self.assertIn("3.0 (1.5x)", plane)
        self.assertTrue(plane.rstrip().endswith("| - |"), plane)  # no target 44 point
        self.assertFalse(any(l.startswith("| Untextured") for l in lines))

    def test_no_target_points_no_table(self):
        self.assertEqual(report.rate_control_speed([{"model": "A", "encode_s": 1.0, "rd": [point("default", 1.0)]}]),
                         [])


if __name__ == "__main__":
    unittest.main()
