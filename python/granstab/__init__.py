"""granstab from Python (docs/python.md).

The commands run in this process with the same code, outputs and error messages as the
``granstab`` executable; each function takes the command's options as keyword arguments and
returns a result object read from the files the command wrote. Runs release the GIL; a
``progress(label, done, total, detail)`` callback is called at most every 0.1 s (tqdm works:
see docs/python.md); Ctrl-C stops a run (a dynamic run writes its checkpoint first).
"""
import os
import tempfile

from ._core import Configuration, Error, run
from ._results import CompareResult, Q1Result, Result, SicResult, read_csv

__all__ = ["Configuration", "Error", "run", "q1", "compare", "sic", "prepare", "biaxial", "info",
           "read_csv", "Result", "Q1Result", "CompareResult", "SicResult"]


def _options(**options):
    """Keyword arguments as command-line options: foo_bar=1 -> --foo-bar 1, True -> the flag,
    False / None -> absent, a list -> the option repeated."""
    args = []
    for key, value in options.items():
        if value is None or value is False:
            continue
        flag = "--" + key.replace("_", "-")
        if value is True:
            args.append(flag)
        elif isinstance(value, (list, tuple)):
            for v in value:
                args += [flag, str(v)]
        else:
            args += [flag, repr(value) if isinstance(value, float) else str(value)]
    return args


def _toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, float):
        return repr(v)
    return str(v)


def _settings(sections):
    """TOML sections as keyword arguments (material={"mu": 0.5}) -> --set material.mu=0.5."""
    args = []
    for section, values in sections.items():
        if not isinstance(values, dict):
            raise TypeError(f"{section}: expected a dict of settings (a [{section}] table)")
        for key, value in values.items():
            args += ["--set", f"{section}.{key}={_toml_value(value)}"]
    return args


def _out_dir(out, name):
    return out if out is not None else tempfile.mkdtemp(prefix=f"granstab-{name}-")


def q1(sample, *, out=None, dq=1e-3, progress=None, quiet=True, **options):
    """Static stepping to the loss of stability (``granstab q1``).

    Options as on the command line, e.g. ``mu=0.25``, ``kt_ratio=0.5``, ``dq_min=1e-7``,
    ``control="strain"``, ``max_steps=100``, ``stop=0.5``, ``hill="every"`` (or a stride, or
    False), ``steps="fixed"`` (default adaptive), ``polish=True``,
    ``clip_to_cone=True``, ``set=["material.zeta=0.5"]``. Returns a Q1Result; the files are in
    ``out`` (a new temporary directory when not given)."""
    out = _out_dir(out, "q1")
    hill = options.pop("hill", None)  # None: the default stride; False: off; "every" or N
    args = ["q1", os.fspath(sample), "--dq", repr(float(dq)), "--out", os.fspath(out)]
    if hill is not None and hill is not True:
        args += ["--hill", "off" if hill is False else str(hill)]
    args += _options(quiet=quiet, **options)
    run(args, progress)
    return Q1Result(out)


def compare(sample, *, dq, out=None, progress=None, quiet=True, **options):
    """Static against dynamic SIC from the same state (``granstab compare``); options as on the
    command line (``mu``, ``kt_ratio``, ``q_max``, ``static_substeps``, ``probe_states``, ...).
    Returns a CompareResult."""
    out = _out_dir(out, "compare")
    args = ["compare", os.fspath(sample), "--dq", repr(float(dq)), "--out", os.fspath(out)]
    args += _options(quiet=quiet, **options)
    run(args, progress)
    return CompareResult(out)


def sic(sample, *, dq, hybrid=True, out=None, progress=None, quiet=True, **options):
    """The SIC biaxial test (``granstab sic``, docs/hybrid.md): with ``hybrid=True`` static
    stepping inside the stability intervals and MD across the rearrangements, with False every
    increment by MD. Options as on the command line (``mu``, ``epsilon_2_end``, ``q_max``,
    ``epsilon_2_max``, ``dq_min``, ``pictures``, ...). Returns a SicResult."""
    out = _out_dir(out, "sic")
    args = ["sic", os.fspath(sample), "--dq", repr(float(dq)), "--out", os.fspath(out)]
    args += _options(hybrid=hybrid, quiet=quiet, **options)
    run(args, progress)
    return SicResult(out)


def _protocol(command, settings, sections, progress, quiet):
    with tempfile.TemporaryDirectory(prefix="granstab-settings-") as tmp:
        if settings is None:
            settings = os.path.join(tmp, "settings.toml")
            open(settings, "w").close()
        args = [command, os.fspath(settings)] + _settings(sections)
        if quiet:
            args.append("--quiet")
        run(args, progress)


def _output_path(settings, sections, key):
    """Where a protocol wrote its output `key` ([output] KEY): from the keyword arguments
    (relative to the working directory) or from the settings file (relative to its directory)."""
    value = sections.get("output", {}).get(key)
    if value is not None:
        return os.path.abspath(value)
    if settings is None:
        return None
    import tomllib
    with open(settings, "rb") as f:
        value = tomllib.load(f).get("output", {}).get(key)
    return None if value is None else os.path.join(os.path.dirname(os.path.abspath(settings)), value)


def prepare(settings=None, *, progress=None, quiet=True, **sections):
    """Isotropic compaction (``granstab prepare``). ``settings``: a TOML file (optional); each
    keyword argument is a TOML table, e.g. ``sample={"n": 100, "seed": 2}``,
    ``output={"sample": "s.granstab"}`` (docs/protocols.md). Returns the prepared Configuration
    (the command's JSON summary is beside the sample file, as on the command line)."""
    _protocol("prepare", settings, sections, progress, quiet)
    return Configuration.load(_output_path(settings, sections, "sample"))


def biaxial(settings=None, *, progress=None, quiet=True, **sections):
    """Biaxial test, SRC or SIC (``granstab biaxial``); settings and tables as for prepare.
    Returns a Result with the summary's fields and ``curve`` (the output CSV)."""
    _protocol("biaxial", settings, sections, progress, quiet)
    csv = _output_path(settings, sections, "csv")
    summary = _output_path(settings, sections, "summary") or os.path.splitext(csv)[0] + ".json"
    return Result(None, summary, {"curve": csv})


def info(sample):
    """The measurements of a sample file (``granstab info``) and its start-state findings, as a
    dict."""
    c = Configuration.load(os.fspath(sample))
    d = c.measure()
    d["start"] = c.check_start()
    return d
