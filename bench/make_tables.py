#!/usr/bin/env python3
"""Turns the runs of bench/dynamic_benchmark.sh into Markdown tables (standard library only)."""
import json
import os
import sys

out, frames = sys.argv[1], int(sys.argv[2])
seqs = ["static", "low", "high", "high_blur"]
modes = ["orb", "T", "TK", "TG", "TKG"]


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def cell(seq, mode):
    d = os.path.join(out, "runs", seq, mode)
    return load(os.path.join(d, "eval.json")) or {}, load(os.path.join(d, "timing.json")) or {}, \
        load(os.path.join(d, "dynamic_eval.json"))


def fmt(x, nd=4):
    return "—" if x is None else f"{x:.{nd}f}"


def table(title, value):
    print(f"\n### {title}\n")
    print("| sequence | " + " | ".join(modes) + " |")
    print("|---" * (len(modes) + 1) + "|")
    for s in seqs:
        if not os.path.isdir(os.path.join(out, "runs", s)):
            continue
        print(f"| {s} | " + " | ".join(value(*cell(s, m)) for m in modes) + " |")


def stat(ev, key, field):
    return ev.get(key, {}).get(field)


def tracked(ev):
    # The run processed `frames` frames; eval counts the trajectory's poses.
    n = ev.get("estimate_poses")
    return None if n is None else 100.0 * n / frames


print(f"# Dynamic benchmark ({frames} frames per sequence, deterministic runs)\n")
print("Composites: real people (cut out of real photos) walking their own 3-D paths through the real "
      "TUM fr1_xyz sequence. low = 1 small slow person; high = 4 large fast people; high_blur = high "
      "with motion blur on 30 % of the frames (detector misses).")
table("ATE RMSE / S.D. (m)  — cf. the paper's Table 1 and 3",
      lambda ev, t, d: f"{fmt(stat(ev, 'ate_m', 'rmse'))} / {fmt(stat(ev, 'ate_m', 'std'))}")
table("RPE translation RMSE / S.D. (m, 1 s) — cf. Table 2",
      lambda ev, t, d: f"{fmt(stat(ev, 'rpe_translation_m', 'rmse'))} / {fmt(stat(ev, 'rpe_translation_m', 'std'))}")
table("Tracked frames (%)", lambda ev, t, d: fmt(tracked(ev), 1))
table("Dynamic keypoints vs ground-truth masks: precision / recall",
      lambda ev, t, d: "—" if not d else f"{d['precision']:.2f} / {d['recall']:.2f}")

# Timing, as multiples of T = ORB extraction + tracking of the orb baseline (Table 4).
print("\n### Mean time per frame as multiples of T (cf. Table 4)\n")
print("T = mean ORB extraction + tracking per frame of the `orb` run on the same sequence. "
      "Local mapping runs in step with tracking in deterministic runs and is excluded from 'all'.\n")
print("| sequence | mode | T (ms) | YOLO | KALMAN | GEOME | ALL |")
print("|---|---|---|---|---|---|---|")
for s in seqs:
    _, base, _ = cell(s, "orb")
    if not base:
        continue
    T = base["orb_and_tracking"]["mean_ms"]
    for m in modes:
        _, t, _ = cell(s, m)
        if not t:
            continue
        n = t["total"]["count"]

        def per_frame(key):
            return t[key]["mean_ms"] * t[key]["count"] / n if key in t else 0.0
        total = t["total"]["mean_ms"] - per_frame("local_mapping_sync")
        print(f"| {s} | {m} | {T:.1f} | {per_frame('detector') / T:.2f}T | {per_frame('box_tracker') / T:.3f}T | "
              f"{per_frame('geometry') / T:.3f}T | {total / T:.2f}T |")
