"""Reading the files a `tkgslam run` / `eval` leaves behind, for the benchmark table scripts."""
import json


def load(path):
    """The JSON file at `path`, or None when it is missing or not JSON (a run that failed)."""
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def stage_ms_per_frame(timing, stage):
    """timing.json's mean time of `stage` spread over every frame (a stage may run on some frames only)."""
    if stage not in timing:
        return 0.0
    return timing[stage]["mean_ms"] * timing[stage]["count"] / timing["total"]["count"]


def frame_ms(timing):
    """Mean time per frame without local mapping (deterministic runs do it in step with tracking)."""
    return timing["total"]["mean_ms"] - stage_ms_per_frame(timing, "local_mapping_sync")


def posed_untracked(run):
    """"(n)": frames posed by the motion model or interpolated across a short loss (run.json); "" if none."""
    n = run.get("predicted", 0) + run.get("interpolated_lost", 0)
    return f" ({n})" if n else ""
