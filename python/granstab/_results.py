"""Result objects of the granstab functions: the JSON fields as attributes, the curves as numpy
arrays. They are read from the files the command wrote (the same files as on the command line),
once, after the run."""
import json
import os

import numpy as np


def read_csv(path):
    """A CSV file with a header line as a dict of numpy arrays (one per column; empty fields are
    NaN, non-numeric columns stay strings)."""
    with open(path) as f:
        header = f.readline().strip().split(",")
        rows = [line.rstrip("\n").split(",") for line in f if line.strip()]
    columns = {}
    for k, name in enumerate(header):
        values = [r[k] if k < len(r) else "" for r in rows]
        try:
            columns[name] = np.array([float(v) if v != "" else np.nan for v in values])
        except ValueError:
            columns[name] = np.array(values)
    return columns


class Result:
    """The summary JSON's fields as attributes (``r.q1``, ``r.criterion``, ...), the full dict as
    ``r.summary``, the output directory as ``r.out``; curves as dicts of numpy arrays."""

    def __init__(self, out, summary_file, curves):
        self.out = out
        with open(os.path.join(out, summary_file) if out else summary_file) as f:
            self.summary = json.load(f)
        for key, value in self.summary.items():
            if key.isidentifier() and not hasattr(self, key):
                setattr(self, key, value)
        for name, path in curves.items():
            setattr(self, name, read_csv(path) if os.path.exists(path) else None)

    def __repr__(self):
        fields = ", ".join(f"{k}={self.summary[k]!r}" for k in list(self.summary)[:4])
        return f"{type(self).__name__}({fields}, ...)"


class Q1Result(Result):
    """granstab q1: q1, q1_bracket, criterion, detail, n_sliding_at_q1, q_max_rigid, material, ...;
    ``curve`` (static_curve.csv: step, load, q, epsilon_1, epsilon_2, epsilon_v, n_sliding, hill,
    det_sign, ..., interpolated) and ``mode`` (unstable_mode.csv)."""

    def __init__(self, out):
        super().__init__(out, "q1.json", {"curve": os.path.join(out, "static_curve.csv"),
                                          "mode": os.path.join(out, "unstable_mode.csv")})


class CompareResult(Result):
    """granstab compare: the fields of compare.json; ``static_curve``, ``dynamic_curve`` and
    ``matched`` as dicts of numpy arrays."""

    def __init__(self, out):
        super().__init__(out, "compare.json", {
            "static_curve": os.path.join(out, "static_curve.csv"),
            "dynamic_curve": os.path.join(out, "dynamic_curve.csv"),
            "matched": os.path.join(out, "matched.csv")})


class SicResult(Result):
    """granstab sic: the fields of sic.json (stop_reason, stability_intervals, rearrangements,
    rearrangement_jump_epsilon_2, md_steps, static_seconds, ...); ``curve`` (sic_curve.csv, its
    ``method`` column "static" / "dynamic" as strings)."""

    def __init__(self, out):
        super().__init__(out, "sic.json", {"curve": os.path.join(out, "sic_curve.csv")})
