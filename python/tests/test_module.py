"""The granstab Python module against the executable (issue #22): same data, same results, same
messages. Run by ctest (python_module) with PYTHONPATH at the build tree's package, GRANSTAB_EXE
the executable of the same build and GRANSTAB_SOURCE_DIR the source tree."""
import json
import os
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import granstab

SOURCE = os.environ.get("GRANSTAB_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "../.."))
EXE = os.environ.get("GRANSTAB_EXE", "granstab")
EXE = os.path.abspath(EXE) if os.sep in EXE else EXE
SAMPLE = os.path.join(SOURCE, "data", "samples", "periodic-n100-k1e4.granstab")


def cli(*args, cwd=None):
    return subprocess.run([EXE, *args], cwd=cwd, capture_output=True, text=True,
                          env=dict(os.environ, OMP_NUM_THREADS="1"))


def without_timings(summary):
    """A q1.json without what depends on the clock or on where the run was started."""
    return {k: v for k, v in summary.items() if "seconds" not in k and k != "sample"}


def test_configuration_round_trip(tmp_path):
    c = granstab.Configuration.load(SAMPLE)
    assert c.n_disks == 100 and c.boundary == "periodic"
    assert c.x.shape == (100,) and c.x.dtype == np.float64
    assert c.contact_i.shape == (c.n_contacts,)
    out = tmp_path / "copy.granstab"
    c.save(str(out))
    d = granstab.Configuration.load(str(out))
    for name in ["x", "y", "radius", "mass", "vx", "vy", "omega", "theta", "contact_i",
                 "contact_j", "delta_t", "contact_status", "length", "sigma_ext"]:
        np.testing.assert_array_equal(getattr(c, name), getattr(d, name), err_msg=name)
    assert (c.k_n, c.k_t, c.mu) == (d.k_n, d.k_t, d.mu)
    assert c.measure()["z"] == d.measure()["z"]


def test_arrays_are_views_of_the_configuration(tmp_path):
    c = granstab.Configuration.load(SAMPLE)
    x = c.x
    x[3] += 0.25  # writes the configuration itself
    assert c.x[3] == x[3]
    out = tmp_path / "moved.granstab"
    c.save(str(out))
    assert granstab.Configuration.load(str(out)).x[3] == x[3]
    del c  # the view keeps the configuration alive
    assert np.isfinite(x).all()


def test_measurements_match_info():
    c = granstab.Configuration.load(SAMPLE)
    r = cli("info", "--json", SAMPLE)
    assert r.returncode == 0, r.stderr
    expected = json.loads(r.stdout)
    m = c.measure()
    for key in ["phi", "z", "x0", "q"]:
        assert m[key] == pytest.approx(expected[key], rel=0, abs=0), key
    assert c.phi == m["phi"] and c.z == m["z"]
    assert m["sigma"].shape == (2, 2)
    assert c.check_start()["geometry"] == []


def test_q1_equals_the_command_line_bit_for_bit(tmp_path):
    args = dict(dq=1e-3, mu=0.5, hill=False, stop=0.1)
    r = granstab.q1(SAMPLE, out=str(tmp_path / "py"), **args)
    c = cli("q1", SAMPLE, "--dq", "0.001", "--mu", "0.5", "--no-hill", "--stop", "0.1", "--quiet",
            "--out", str(tmp_path / "cli"))
    assert c.returncode == 0, c.stderr
    with open(tmp_path / "cli" / "q1.json") as f:
        expected = json.load(f)
    assert without_timings(r.summary) == without_timings(expected)
    for name in ["static_curve.csv", "unstable_mode.csv"]:
        py_file, cli_file = tmp_path / "py" / name, tmp_path / "cli" / name
        assert py_file.exists() == cli_file.exists(), name
        if py_file.exists():
            assert py_file.read_bytes() == cli_file.read_bytes(), name
    # The result object: the JSON as attributes, the curve as numpy arrays.
    assert r.material["mu"] == 0.5
    assert isinstance(r.curve["q"], np.ndarray) and r.curve["q"][0] == pytest.approx(0, abs=1e-9)
    assert r.curve["q"][-1] >= 0.1 or r.q1 is not None


def test_hybrid_sic_result(tmp_path):
    r = granstab.sic(SAMPLE, dq=0.01, epsilon_2_end=0.004, pictures=0, out=str(tmp_path / "py"))
    c = cli("sic", SAMPLE, "--dq", "0.01", "--hybrid", "--epsilon-2-end", "0.004", "--pictures",
            "0", "--quiet", "--out", str(tmp_path / "cli"))
    assert c.returncode == 0, c.stderr
    name = "sic_curve.csv"
    assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    assert r.method == "hybrid" and r.stop_reason == "epsilon_2_end"
    methods = list(r.curve["method"])
    assert methods.count("dynamic") == r.rearrangements >= 2
    assert len(r.rearrangement_jump_epsilon_2) == r.rearrangements


def test_malformed_file_raises_the_command_line_message(tmp_path):
    bad = tmp_path / "bad.granstab"
    text = open(SAMPLE).read().splitlines()
    # Damage the second number of the first disk line: the message names file and line.
    first_disk = next(k for k, line in enumerate(text) if line.startswith("disks ")) + 2
    fields = text[first_disk].split()
    fields[1] = "1.0x"
    text[first_disk] = " ".join(fields)
    bad.write_text("\n".join(text) + "\n")
    c = cli("q1", str(bad), "--quiet", "--out", str(tmp_path / "cli"))
    assert c.returncode == 1
    message = c.stderr.strip().removeprefix("granstab: error: ")
    with pytest.raises(granstab.Error) as e:
        granstab.q1(str(bad), out=str(tmp_path / "py"))
    assert str(e.value) == message
    assert str(bad) in str(e.value)
    with pytest.raises(granstab.Error) as e:
        granstab.Configuration.load(str(bad))
    assert str(bad) in str(e.value)
    assert not (tmp_path / "py" / "q1.json").exists()


def test_bad_option_is_a_value_error(tmp_path):
    with pytest.raises(ValueError):
        granstab.q1(SAMPLE, out=str(tmp_path), mu=-1.0)


def test_progress_callback_is_called(tmp_path):
    calls = []
    granstab.q1(SAMPLE, out=str(tmp_path), mu=0.5, hill=False, stop=0.05,
                progress=lambda label, done, total, detail: calls.append((label, done, detail)))
    assert calls, "the callback was never called"
    assert all(label == "q1" for label, _, _ in calls)
    assert "states" in calls[-1][2]


def test_the_gil_is_released_during_a_run(tmp_path):
    ticks = 0
    running = True

    def count():
        nonlocal ticks
        while running:
            ticks += 1
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    start = time.perf_counter()
    granstab.q1(SAMPLE, out=str(tmp_path), mu=0.5, hill=False, progress=None)
    seconds = time.perf_counter() - start
    running = False
    t.join()
    # Held all along, the GIL would let the thread run only between the two calls; released, it
    # ticks about once a millisecond (a tenth of that is asked: the machine is shared).
    assert ticks > 100 * seconds, (ticks, seconds)


def test_ctrl_c_stops_a_static_run_without_outputs(tmp_path):
    import _thread

    def interrupt(label, done, total, detail):
        _thread.interrupt_main()  # as Ctrl-C: Python's handler sets the flag the run checks

    with pytest.raises(KeyboardInterrupt):
        granstab.q1(SAMPLE, out=str(tmp_path), mu=0.5, hill=False, progress=interrupt)
    assert not (tmp_path / "q1.json").exists()


def test_ctrl_c_in_a_dynamic_run_writes_its_checkpoint(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    sent = []

    def interrupt(label, done, total, detail):
        if not sent:
            sent.append(label)
            os.kill(os.getpid(), signal.SIGINT)  # the run's own handler: checkpoint, then stop

    with pytest.raises(KeyboardInterrupt) as e:
        granstab.prepare(sample={"n": 40, "boundary": "periodic", "seed": 7},
                         material={"kappa": 1e3}, output={"sample": "tiny.granstab"},
                         checkpoint={"every_steps": 400}, progress=interrupt)
    assert "resume" in str(e.value)
    checkpoints = [p for p in os.listdir(tmp_path) if p.endswith(".checkpoint")]
    assert checkpoints, os.listdir(tmp_path)
    r = cli("resume", "--quiet", checkpoints[0], cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert granstab.Configuration.load("tiny.granstab").n_disks == 40
