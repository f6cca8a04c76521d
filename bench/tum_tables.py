#!/usr/bin/env python3
"""Turns the runs of bench/tum_benchmark.sh (OUT/runs/SEQUENCE/MODE/) into Markdown tables next to the
numbers the TKG-SLAM paper publishes for the TUM fr3 dynamic sequences (standard library only)."""
import os
import sys

from run_files import frame_ms, load, posed_untracked

out = sys.argv[1]
runs = os.path.join(out, "runs")
ORDER = ["orb", "T", "TK", "TG", "TKG", "TKGp", "TKGa", "TKGl", "TKGt", "TKGf", "TKGs"]

# The paper's Tables 1 and 2 (RMSE / S.D., m; "RPE" is the translational drift over 1 s): its own
# method, CFP-SLAM (its strongest competitor) and DynaSLAM. None = not given in the paper.
PAPER_NAMES = {"freiburg3_sitting_xyz": "s/xyz", "freiburg3_sitting_halfsphere": "s/half",
               "freiburg3_sitting_static": "s/static", "freiburg3_sitting_rpy": "s/rpy",
               "freiburg3_walking_xyz": "w/xyz", "freiburg3_walking_halfsphere": "w/half",
               "freiburg3_walking_static": "w/static", "freiburg3_walking_rpy": "w/rpy"}
PAPER_ATE = {  # sequence: (TKG-SLAM, CFP-SLAM, DynaSLAM)
    "s/xyz": ((0.0089, 0.0046), (0.0090, 0.0042), (0.0127, 0.0060)),
    "s/half": ((0.0249, 0.0138), (0.0147, 0.0069), (0.0186, 0.0086)),
    "s/static": ((0.0071, 0.0036), (0.0053, 0.0027), None),
    "s/rpy": ((0.0282, 0.0201), (0.0253, 0.0154), None),
    "w/xyz": ((0.0129, 0.0067), (0.0141, 0.0072), (0.0164, 0.0086)),
    "w/half": ((0.0214, 0.0114), (0.0237, 0.0114), (0.0296, 0.0157)),
    "w/static": ((0.0071, 0.0033), (0.0066, 0.0030), (0.0068, 0.0032)),
    "w/rpy": ((0.0380, 0.0245), (0.0368, 0.0230), (0.0354, 0.0190)),
}
PAPER_RPE = {
    "s/xyz": ((0.0084, 0.0045), (0.0114, 0.0055), (0.0142, 0.0073)),
    "s/half": ((0.0069, 0.0038), (0.0162, 0.0079), (0.0239, 0.0120)),
    "s/static": ((0.0045, 0.0023), (0.0072, 0.0035), None),
    "s/rpy": ((0.0131, 0.0090), (0.0316, 0.0186), None),
    "w/xyz": ((0.0114, 0.0064), (0.0190, 0.0097), (0.0217, 0.0119)),
    "w/half": ((0.0174, 0.0122), (0.0259, 0.0128), (0.0284, 0.0149)),
    "w/static": ((0.0060, 0.0036), (0.0089, 0.0040), (0.0089, 0.0044)),
    "w/rpy": ((0.0184, 0.0115), (0.0500, 0.0306), (0.0448, 0.0262)),
}
PAPER_COLUMNS = ["paper: TKG-SLAM", "paper: CFP-SLAM", "paper: DynaSLAM"]
# The paper's Table 3, its ablation on the walking sequences: ATE (RMSE, S.D.) of T, TK, TG and TKG
# (its TKG w/half differs from Table 1's; both as published).
PAPER_ABLATION = {
    "w/xyz": {"T": (0.0137, 0.0073), "TK": (0.0131, 0.0068), "TG": (0.0134, 0.0071), "TKG": (0.0129, 0.0067)},
    "w/half": {"T": (0.0247, 0.0164), "TK": None, "TG": (0.0188, 0.0093), "TKG": (0.0188, 0.0091)},
    "w/static": {"T": (0.0076, 0.0031), "TK": (0.0082, 0.0044), "TG": (0.0081, 0.0038), "TKG": (0.0071, 0.0033)},
    "w/rpy": {"T": (0.2504, 0.1146), "TK": (0.0380, 0.0263), "TG": (0.2071, 0.1322), "TKG": (0.0380, 0.0245)},
}


seqs = sorted(d for d in os.listdir(runs) if os.path.isdir(os.path.join(runs, d))) if os.path.isdir(runs) else []
present = {m for s in seqs for m in os.listdir(os.path.join(runs, s))}
modes = [m for m in ORDER if m in present]


def run_file(seq, mode, name):
    return load(os.path.join(runs, seq, mode, name)) or {}


def pair(stats):
    return "—" if not stats else f"{stats['rmse']:.4f} / {stats['std']:.4f}"


def paper_pair(v):
    return "—" if v is None else f"{v[0]:.4f} / {v[1]:.4f}"


def markdown_table(title, columns, rows):
    """Prints a table under a heading; rows are (sequence, [cell per column])."""
    print(f"\n### {title}\n")
    print("| sequence | " + " | ".join(columns) + " |")
    print("|---" * (len(columns) + 1) + "|")
    for s, cells in rows:
        print(f"| {s} | " + " | ".join(cells) + " |")


def table(title, key, paper=None):
    """Our RMSE / S.D. of an eval.json statistic per mode, and the paper's numbers when given."""
    rows = []
    for s in seqs:
        row = [pair(run_file(s, m, "eval.json").get(key)) for m in modes]
        if paper:
            published = paper.get(PAPER_NAMES.get(s, ""))
            row += [paper_pair(v) for v in published] if published else ["—"] * len(PAPER_COLUMNS)
        rows.append((s, row))
    markdown_table(title, modes + (PAPER_COLUMNS if paper else []), rows)


def tracked(seq, mode):
    r = run_file(seq, mode, "run.json")
    return "—" if not r else f"{100.0 * r['tracked_ratio']:.1f}" + posed_untracked(r)


def times(seq, mode):
    t = run_file(seq, mode, "timing.json")
    if not t:
        return "—"
    base = run_file(seq, "orb", "timing.json")
    ms = frame_ms(t)
    return f"{ms:.1f}" + (f" ({ms / base['orb_and_tracking']['mean_ms']:.2f} T)" if base else "")


print("# TUM RGB-D benchmark (deterministic runs)\n")
if not seqs:
    print("No runs found.")
    sys.exit(0)
print("Modes as in `bench/modes.sh` (TKGf = `run --fast`: every frame detected at 320 x 256, one frame ahead, poses 1 frame "
      "late; TKGt: lookahead with tiled detector runs, poses 15 frames late). "
      "ATE and RPE as the TUM scripts compute them (`tkgslam eval`); \"—\" = no run, no ground truth, or not "
      "published. The paper's numbers are its Tables 1 and 2 (Intel i5; its RPE is the translational drift "
      "over 1 s).")
table("ATE RMSE / S.D. (m) — cf. the paper's Table 1", "ate_m", PAPER_ATE)
ablation = [m for m in ("T", "TK", "TG", "TKG") if m in modes]
walking = [s for s in seqs if PAPER_NAMES.get(s) in PAPER_ABLATION]
if ablation and walking:
    markdown_table("Ablation: ATE RMSE / S.D. (m), ours | the paper's Table 3",
                   [c for m in ablation for c in (m, f"paper: {m}")],
                   [(s, [c for m in ablation for c in (pair(run_file(s, m, "eval.json").get("ate_m")),
                                                      paper_pair(PAPER_ABLATION[PAPER_NAMES[s]][m]))])
                    for s in walking])
table("RPE translation RMSE / S.D. (m, 1 s) — cf. the paper's Table 2", "rpe_translation_m", PAPER_RPE)
table("RPE rotation RMSE / S.D. (deg, 1 s)", "rpe_rotation_deg")
markdown_table("Tracked frames (%; in brackets the frames posed by the motion model or interpolated across a short "
               "loss)", modes, [(s, [tracked(s, m) for m in modes]) for s in seqs])
markdown_table("Mean time per frame (ms; in brackets as multiples of T, the `orb` run's ORB extraction + tracking, "
               "cf. the paper's Table 4; local mapping excluded)", modes, [(s, [times(s, m) for m in modes]) for s in seqs])
