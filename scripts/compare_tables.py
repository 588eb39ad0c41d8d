#!/usr/bin/env python3
"""Markdown tables of the comparisons made by scripts/compare.sh, from each
run's OUT/eval/summary.json (means over the frames)."""
import json
import os
import sys


def load(out, name):
    path = os.path.join(out, name, "eval", "summary.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def fmt(v, digits=3):
    if v is None:
        return "–"
    if isinstance(v, float):
        if v != 0 and (abs(v) < 1e-3 or abs(v) >= 1e4):
            return f"{v:.2e}"
        return f"{v:.{digits}f}"
    return str(v)


def table(out, title, rows, columns):
    print(f"\n### {title}\n")
    print("| run | " + " | ".join(label for label, _ in columns) + " |")
    print("|---|" + "---|" * len(columns))
    for name in rows:
        s = load(out, name)
        if s is None:
            print(f"| {name} | " + " | ".join("(missing)" for _ in columns) + " |")
            continue
        print(f"| {name} | " + " | ".join(fmt(s.get(key)) for _, key in columns) + " |")


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "out/compare"
    table(out, "Every generated scene, default settings",
          ["rotation-patches", "split-patches", "merge-patches", "drop-patches"],
          [("patches", "patches"), ("uncovered area", "uncovered_area_mean"), ("uncovered texels", "uncovered_texels_mean"),
           ("ghosting mean", "ghosting_mean"), ("D_T median", "distortion_median"), ("D_T p95", "distortion_p95"),
           ("Q_V < 0.5", "quality_below_half"), ("warp: advected", "warp_advected"), ("warp: random", "warp_random"),
           ("flow EPE px", "flow_endpoint_px"), ("speed px", "flow_speed_px")])
    table(out, "Density-based vs linear fading (Fig. 7)",
          ["split-patches", "split-linear-fading", "drop-patches", "drop-linear-fading"],
          [("patches", "patches"), ("fading out (close)", "fading_out_close"),
           ("ghosting mean", "ghosting_mean"), ("ghosting p95", "ghosting_p95"),
           ("lifetime (frames)", "patch_lifetime_mean"), ("uncovered area", "uncovered_area_mean")])
    table(out, "Ellipsoid + plane vs sphere criterion, drop meeting the pool (Figs. 3, 5)",
          ["drop-patches", "drop-sphere", "drop-plain", "drop-sphere-plain"],
          [("uncovered area", "uncovered_area_mean"), ("uncovered texels", "uncovered_texels_mean"),
           ("patches", "patches"), ("ghosting mean", "ghosting_mean")])
    table(out, "Contrast-preserving (Eq. 7) vs linear blending",
          ["split-patches", "split-linear-blend"],
          [("σ ratio R", "contrast_r"), ("σ ratio G", "contrast_g"), ("σ ratio B", "contrast_b"),
           ("spectrum distance", "spectrum_distance"), ("warping error", "warp_advected")])
    table(out, "Texture–flow agreement (Figs. 8, 9, 15) and the flow-map baseline",
          ["rotation-patches", "rotation-flowmap", "split-patches", "split-flowmap", "drop-patches"],
          [("warp: advected", "warp_advected"), ("warp: not moving", "warp_fixed"), ("warp: random", "warp_random"),
           ("flow EPE px", "flow_endpoint_px"), ("speed px", "flow_speed_px"), ("flow AE deg", "flow_angular_deg"),
           ("σ ratio G", "contrast_g"), ("spectrum distance", "spectrum_distance")])


if __name__ == "__main__":
    main()
