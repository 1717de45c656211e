#!/usr/bin/python3
"""gltf-warp-compare on a model the encoder cuts into atlas pages (ctest bench.compare_cut_model).

The encoder appends a cut primitive's parts after its mesh's own primitives,
and its report names them by their decoded indices; compare once indexed the
source with those (out of bounds). A generated torus with a 1024^2 texture
and --max-atlas-size 256 is cut (--always-implicit: the
parts would otherwise keep explicit UVs, which are smaller); compare must run and measure it.

  test_compare_cut.py GLTF_WARP GLTF_WARP_COMPARE WORKDIR
"""
import json
import os
import subprocess
import sys

gw, cmp, work = sys.argv[1:4]
os.makedirs(work, exist_ok=True)
model = os.path.join(work, "torus.glb")
subprocess.run([gw, "sample", "--shape", "torus", "--faces", "4000", "--texture-size", "1024", "-o", model],
               check=True)
res = subprocess.run([cmp, model, "--work", os.path.join(work, "w"), "--runs", "1", "--max-atlas-size", "256",
                      "--always-implicit", "--no-rd", "--render-size", "128", "--render-small", "0"],
                     check=True, capture_output=True, text=True)
r = json.loads(res.stdout)
assert r["primitives_textured"] == 1, r["primitives_textured"]
assert r["primitives_replaced"] > 1, f"not cut: {r['primitives_replaced']} primitive(s) replaced"
assert r["psnr_faces_skipped"] == 0, r["psnr_faces_skipped"]
assert r["psnr_samples"] > 0
assert 30 < r["psnr_ours"] < 99, r["psnr_ours"]
default = next(p for p in r["rd"] if p["curve"] == "ours" and p["setting"] == "default")
assert default["render_pixels"] > 1000, default["render_pixels"]
assert 25 < default["psnr_render"] <= 99, default["psnr_render"]
# Weighted by 3D area too: every face of the cut parts found its source face and its area.
assert 25 < default["psnr_area"] <= 99, default["psnr_area"]
print(f"cut into {r['primitives_replaced']} primitives: surface {r['psnr_ours']:.2f} dB "
      f"({default['psnr_area']:.2f} dB by area), render {default['psnr_render']:.2f} dB")
