#!/usr/bin/python3
"""Unit tests of benchmarks/layout_report.py on a synthetic encode (run by ctest)."""
import json
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import layout_report  # noqa: E402


def prim(tris, seams, rect_fill, implicit=True, version="1.1"):
    return {"implicit_uv": implicit, "version": version, "triangles": tris, "patches": 3, "solve_patches": 0,
            "seam_edges": seams, "rect_fill": rect_fill, "holes": 0, "max_distortion": 1.2, "flipped": 0,
            "bitstream_bytes": 100}


class LayoutReport(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.d = self.dir.name

    def tearDown(self):
        self.dir.cleanup()

    def encode(self, name, prims, log):
        info, lg = os.path.join(self.d, name + ".json"), os.path.join(self.d, name + ".log")
        json.dump({"image_bytes": 500, "primitives": prims}, open(info, "w"))
        open(lg, "w").write(log)
        return info, lg

    def test_row_weighs_primitives_by_triangles_and_pages_by_texels(self):
        info, log = self.encode("a", [prim(100, 10, 0.9), prim(300, 30, 0.5), prim(50, 0, 0.0, implicit=False)],
                                "atlas 0: 100x100, fill 80.0%, overlapping\natlas 1: 200x100 + 100x100, fill 40.0%, x\n")
        r = layout_report.row("m", "unfold", info, log, "1.0", "3.5")
        self.assertEqual(r["seam_edges"], 40)  # the explicit-UV primitive does not count
        self.assertEqual(r["triangles"], 400)
        self.assertAlmostEqual(r["rect_fill"], (100 * 0.9 + 300 * 0.5) / 400)
        self.assertAlmostEqual(r["atlas_fill"], (10000 * 0.8 + 30000 * 0.4) / 40000)
        self.assertAlmostEqual(r["encode_s"], 2.5)

    def test_no_implicit_primitive_gives_no_row(self):
        info, log = self.encode("b", [prim(10, 1, 1.0, implicit=False)], "")
        self.assertIsNone(layout_report.row("m", "greedy", info, log, "0", "1"))

    def test_table_divides_seams_by_greedy_and_judges_the_goals(self):
        rows = []
        source = ("             source UV charts          7       40                "
                  "(52 of them bound our patches; 12.5% of the surface past tau at each chart's own scale; "
                  "not discs: 2 charts, 40.0% of the surface)\n")
        for variant, seams, fill in (("greedy", 100, "50.0"), ("unfold", 60, "70.0"), ("mixed", 45, "76.0"),
                                     ("crossing", 30, "77.0")):
            info, log = self.encode(variant, [prim(10, seams, 0.72)], source + f"atlas 0: 10x10, fill {fill}%,\n")
            rows.append(layout_report.row("m", variant, info, log, "0", "1"))
        self.assertEqual((rows[2]["source_charts"], rows[2]["source_seam_edges"], rows[2]["bound_seam_edges"]),
                         (7, 40, 52))
        self.assertAlmostEqual(rows[2]["source_beyond_tau"], 0.125)
        self.assertEqual(rows[2]["source_non_disc_charts"], 2)
        self.assertAlmostEqual(rows[2]["source_non_disc_area"], 0.4)
        for variant in ("greedy", "unfold"):  # a plane: no seam to halve
            info, log = self.encode("p" + variant, [prim(2, 0, 1.0)], "atlas 0: 10x10, fill 90.0%,\n")
            rows.append(layout_report.row("plane", variant, info, log, "0", "1"))
        jsonl = os.path.join(self.d, "layout.jsonl")
        open(jsonl, "w").write("\n".join(json.dumps(r) for r in rows) + "\n")
        layout_report.table(jsonl, self.d)
        md = open(os.path.join(self.d, "solve_layout.md")).read()
        self.assertIn("| m | mixed | 1.1 | 3 (0) | 45 | 0.45 | 76.0% | 0.720 |", md)
        self.assertIn("| m | unfold | 1.1 | 3 (0) | 60 | 0.60 |", md)
        self.assertIn("| plane | unfold | 1.1 | 3 (0) | 0 | - |", md)
        self.assertIn("interior seam edges <= 0.5x greedy: met on 1 of 1 (1 models without greedy seams", md)
        self.assertIn("atlas fill >= 75%: met on 2 of 2.", md)
        # The source's charts: 52 bound seams > 0.5x greedy's 100; crossing is reported, not judged.
        self.assertIn("| m | 7 (2) | 40 | 12.5% | 40.0% | 52 | 50 | 45 | 30 |", md)
        self.assertIn("fewer than the seams the source's charts bind: m.", md)
        self.assertIn("| m | crossing | 1.1 | 3 (0) | 30 | 0.30 |", md)


if __name__ == "__main__":
    unittest.main()
