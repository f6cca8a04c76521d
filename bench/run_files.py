"""Reading the files a `tkgslam run` / `eval` leaves behind, for the benchmark table scripts."""
import json


def load(path):
    """The JSON file at `path`, or None when it is missing or not JSON (a run that failed)."""
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None
