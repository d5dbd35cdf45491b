"""The Python package against the command: same arrays bit for bit, same
errors, ensembles equal to sequential runs, interruption.

The command binary is taken from $VESELOV_BIN, else from
$CARGO_TARGET_DIR (or target/) /debug/veselov; `.ci/run` sets it.
"""

import collections.abc
import contextlib
import inspect
import os
import re
import signal
import shutil
import subprocess
import threading
from pathlib import Path

import numpy as np
import pytest

import veselov
import veselov.dask

ROOT = Path(__file__).resolve().parents[3]
EXAMPLES = ROOT / "examples"


def command():
    env = os.environ.get("VESELOV_BIN")
    if env:
        return Path(env)
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return target / "debug" / "veselov"


def shortened(name, tmp_path, **keys):
    """The example `name` with `keys` overridden, as a file for the command."""
    text = (EXAMPLES / name).read_text()
    if keys:
        status, text, key = veselov._native.merge(text, veselov.toml_text(keys))
        assert status == "ok", text
    path = tmp_path / name
    path.write_text(text)
    return path


def same_bits(a, b):
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return a.shape == b.shape and np.array_equal(a.view(np.int64), b.view(np.int64))


# One scenario of each kind: mechanics (fixed step), SEM (variable step),
# custom expression system, rigid body, lattice field, CFK field, beam, rod.
KINDS = [
    ("kepler.toml", {"time.t_end": 20.0}),
    ("kepler_sem.toml", {"time.t_end": 10.0}),
    ("kepler_custom.toml", {"time.t_end": 10.0}),
    ("rigid_body.toml", {"time.t_end": 10.0}),
    ("wave.toml", {"time.t_end": 5.0}),
    ("klein_gordon_complex.toml", {"time.t_end": 2.0}),
    ("beam_free_free.toml", {"time.t_end": 0.1}),
    ("beam_end_force.toml", {"time.t_end": 0.1}),
    ("rod_timoshenko.toml", {"time.t_end": 10.0}),
]


@pytest.mark.parametrize("name,keys", KINDS)
def test_arrays_equal_the_commands_files_bit_for_bit(name, keys, tmp_path):
    exe = command()
    if not exe.exists():
        if os.environ.get("VESELOV_BIN"):
            pytest.fail(f"VESELOV_BIN={exe} does not exist")
        pytest.skip(f"no command binary at {exe} (set VESELOV_BIN)")
    path = shortened(name, tmp_path, **keys)
    cmd_dir = tmp_path / "command"
    subprocess.run([str(exe), "run", str(path), "--out", str(cmd_dir), "--quiet"], check=True)
    reference = veselov.read_dir(cmd_dir)
    assert reference.tables or reference.arrays

    kept = veselov.run(path, out=tmp_path / "python")
    unkept = veselov.run(path)
    for r in (kept, unkept):
        assert r.status == "ok" == r.summary["status"]
        assert set(r.tables) == set(reference.tables)
        assert set(r.arrays) == set(reference.arrays)
        for stem, table in reference.tables.items():
            assert list(r.tables[stem]) == list(table)
            for column, values in table.items():
                assert same_bits(r.tables[stem][column], values), (stem, column)
        for stem, values in reference.arrays.items():
            assert same_bits(r.arrays[stem], values), stem
    # The kept files are the command's, byte for byte (summary aside: wall time).
    for f in cmd_dir.iterdir():
        if f.suffix in (".csv", ".npy"):
            assert (tmp_path / "python" / f.name).read_bytes() == f.read_bytes(), f.name


def test_csv_and_npy_read_back_agree_bit_for_bit(tmp_path):
    # read_dir takes a table from its NPY file when there is one: the CSV
    # file must hold the same numbers, bit for bit.
    r = veselov.run(EXAMPLES / "kepler.toml", out=tmp_path / "run")
    traj = r.arrays["trajectory"]
    from_csv = veselov._read_csv(tmp_path / "run" / "trajectory.csv")
    assert list(from_csv) == list(r.tables["trajectory"])
    for i, column in enumerate(from_csv):
        assert same_bits(traj[:, i], from_csv[column])
        assert same_bits(r[column], from_csv[column])


def test_bad_scenario_raises_scenario_error_naming_the_key(tmp_path):
    base = {
        "model": {"name": "kepler"},
        "method": {"name": "midpoint", "dt": 0.01},
        "time": {"t_end": 1.0},
    }
    bad_dt = {**base, "method": {"name": "midpoint", "dt": -1.0}}
    with pytest.raises(veselov.ScenarioError) as e:
        veselov.run(bad_dt)
    assert e.value.key == "method.dt"
    assert "expected a finite number > 0" in str(e.value)

    bad_type = (EXAMPLES / "kepler.toml").read_text().replace("dt = 0.01", 'dt = "fast"')
    with pytest.raises(veselov.ScenarioError) as e:
        veselov.run(bad_type)
    assert e.value.key == "method.dt"

    with pytest.raises(veselov.ScenarioError) as e:
        veselov.run({**base, "initial": {"q": [1.0], "p": [0.0, 1.0]}})
    assert e.value.key == "initial.q"

    with pytest.raises(veselov.ScenarioError) as e:
        veselov.ensemble(base, [{}, {"method.dt": 0.0}])
    assert e.value.key == "method.dt" and "member 1" in str(e.value)


def test_a_run_failing_mid_way_returns_its_partial_arrays():
    # q'' = q³ from q = 1, p = 1 blows up at a finite time t* < 2: the run stops there.
    scenario = {
        "model": {
            "name": "custom",
            "coordinates": ["x"],
            "lagrangian": "0.5*x_dot^2 + 0.25*x^4",
        },
        "method": {"name": "midpoint", "dt": 0.01},
        "time": {"t_end": 5.0},
        "initial": {"q": [1.0], "p": [1.0]},
    }
    r = veselov.run(scenario)
    assert r.status == "error" == r.summary["status"]
    assert r.summary["failure"] is not None and r.message
    steps = r.summary["steps"]
    assert 0 < steps < 500
    assert len(r["t"]) == steps + 1
    assert np.all(np.isfinite(r["x"]))


def vdp_members(n):
    rng = np.random.default_rng(4)
    return [{"initial.q": [float(a), float(b)], "time.t_end": 5.0} for a, b in rng.normal(size=(n, 2))]


def test_ensemble_equals_sequential_runs():
    members = vdp_members(6)
    together = veselov.ensemble(EXAMPLES / "van_der_pol.toml", members, workers=2)
    calls = []
    alone = veselov.ensemble(EXAMPLES / "van_der_pol.toml", members, workers=1, progress=lambda d, n: calls.append(d))
    assert calls[-1] == len(members)
    for i, m in enumerate(members):
        seq = veselov.run(veselov._native.merge((EXAMPLES / "van_der_pol.toml").read_text(), veselov.toml_text(m))[1])
        for r in (together[i], alone[i]):
            assert r.status == "ok"
            assert r["q1"][0] == m["initial.q"][0]
            for c in seq.tables["trajectory"]:
                assert same_bits(r[c], seq[c]), (i, c)


def test_dask_local_cluster_equals_local_ensemble():
    distributed = pytest.importorskip("distributed")
    members = vdp_members(5)
    local = veselov.ensemble(EXAMPLES / "van_der_pol.toml", members)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            from veselov import dask as vdask

            remote = vdask.ensemble(client, EXAMPLES / "van_der_pol.toml", members, batch=2)
    assert len(remote) == len(local)
    for a, b in zip(local, remote):
        assert a.status == b.status == "ok"
        for c in a.tables["trajectory"]:
            assert same_bits(a[c], b[c])


@pytest.mark.parametrize("signum", [signal.SIGINT])
def test_a_signal_interrupts_a_run(signum, tmp_path):
    long = {"time.t_end": 1.0e6, "output.every": 1000}
    text = veselov._native.merge((EXAMPLES / "kepler.toml").read_text(), veselov.toml_text(long))[1]
    # The test is of the run's handling of Python's own Ctrl-C handler
    # (raising KeyboardInterrupt) with the signal deliverable: it sets both
    # whatever the libraries of earlier tests (dask's cluster) left, since a
    # handler that swallows the signal lets the run go on, by design. The
    # threads the run starts inherit this thread's signal mask.
    handler = signal.signal(signum, signal.default_int_handler)
    blocked = signal.pthread_sigmask(signal.SIG_UNBLOCK, [signum])
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signum))
    timer.start()
    try:
        r = veselov.run(text, out=tmp_path / "run")
    finally:
        timer.cancel()
        signal.signal(signum, handler)
        signal.pthread_sigmask(signal.SIG_SETMASK, blocked)
    assert r.status == "interrupted" == r.summary["status"], f"before the test: handler {handler}, blocked {blocked}"
    steps = r.summary["steps"]
    assert 0 < steps < 1e8
    assert len(r["t"]) >= 1
    assert np.all(np.isfinite(r["energy"]))


SECTION_6_ROD = {
    "model": {
        "name": "cosserat-rod",
        "length": 1.0,
        "nodes": 21,
        "mass_per_length": 1.0,
        "inertia_density": [0.1, 0.1, 0.2],
        "shear_stiffness": [1.0, 1.0, 10.0],
        "bending_stiffness": [1.0, 1.0, 0.5],
    },
    "initial": {
        "position": ["0.05*sin(3*s) + 0.2*t", "0.1*t*cos(2*s)", "s + 0.01*t"],
        "rotation_vector": ["0.3*s", "0.5*t", "0.2*s^2 + 0.4*t"],
    },
    "time": {"t_end": 0.4025, "dt": 0.005},
}


def test_a_rod_from_raw_data_and_an_initial_motion_keeps_the_reference_momenta():
    # Seed 003 §6 through the same parser as the command: the final momenta
    # of an independent implementation of the march, to 1e-9.
    r = veselov.run(SECTION_6_ROD)
    assert r.status == "ok"
    momentum = r.tables["momentum"]
    reference = {
        "P_x": 0.200427242086534,
        "P_y": 0.0448994415466,
        "P_z": 0.010470853044042,
        "L_x": -0.010241443704355,
        "L_y": 0.141408132575811,
        "L_z": 0.080355900419697,
    }
    for name, value in reference.items():
        assert abs(momentum[name][-1] - value) <= 1e-9, name
    assert abs(momentum["t"][0] - 0.005) < 1e-15 and abs(momentum["t"][-1] - 0.4025) < 1e-15
    bad = {**SECTION_6_ROD, "model": {**SECTION_6_ROD["model"], "inertia_density": [0.1, 0, 0, 0, 0.1, 0.01, 0, 0.02, 0.2]}}
    with pytest.raises(veselov.ScenarioError) as e:
        veselov.run(bad)
    assert e.value.key == "model.inertia_density[7]"


def test_catalogues_and_verify():
    names = {m["name"] for m in veselov.models()}
    assert {"kepler", "van-der-pol", "rigid-body"} <= names
    structures = {m["name"]: m for m in veselov.structures()}
    assert set(structures) == {"beam", "cosserat-rod"}
    assert "shear_coefficient" in structures["cosserat-rod"]["keys"]
    assert any(m["name"] == "midpoint" for m in veselov.methods())
    r = veselov.verify(EXAMPLES / "harmonic.toml", dt=[0.1, 0.05, 0.025])
    assert r.status == "ok"
    assert r.tables


def test_overrides_merge_dotted_keys_and_tables():
    text = veselov.toml_text({"method.dt": 0.5, "method": {"name": "midpoint"}, "initial.q": [0.1, 2]})
    assert text == '"method" = { "dt" = 0.5, "name" = "midpoint" }\n"initial" = { "q" = [0.1, 2] }\n'
    status, merged, _ = veselov._native.merge((EXAMPLES / "van_der_pol.toml").read_text(), text)
    assert status == "ok"
    assert 'name = "midpoint"' in merged and "dt = 0.5" in merged and "stages = 3" in merged


# Dunder methods that are public through syntax (`r[name]`, `name in r`).
PROTOCOL = {"__getitem__", "__contains__", "__iter__", "__len__", "__call__"}


def sections(doc):
    """{title: text} of a NumPy-style docstring's sections (a title
    underlined with as many dashes)."""
    lines = inspect.cleandoc(doc or "").splitlines()
    titles = [
        i
        for i in range(len(lines) - 1)
        if lines[i].strip() and re.fullmatch(r"-+", lines[i + 1].strip()) and len(lines[i + 1].strip()) == len(lines[i].strip())
    ]
    ends = titles[1:] + [len(lines)]
    return {lines[i].strip(): "\n".join(lines[i + 2 : end]) for i, end in zip(titles, ends)}


def public_api():
    """(dotted name, object) of every public function, class and method of
    the package: what `veselov` and `veselov.dask` define under names without
    a leading underscore (and list in `__all__`), the methods of those
    classes, and the functions of the native module."""
    found = []
    for module in (veselov, veselov.dask):
        names = set(module.__all__) | {n for n in vars(module) if not n.startswith("_")}
        for name in sorted(names):
            obj = getattr(module, name)
            if not (inspect.isfunction(obj) or inspect.isclass(obj)):
                continue
            if name not in module.__all__ and obj.__module__ != module.__name__:
                continue  # imported for use here, not part of the package
            found.append((f"{module.__name__}.{name}", obj))
            if inspect.isclass(obj):
                for attr, member in vars(obj).items():
                    if inspect.isfunction(member) and (not attr.startswith("_") or attr in PROTOCOL):
                        found.append((f"{module.__name__}.{name}.{attr}", member))
    for name in sorted(dir(veselov._native)):
        obj = getattr(veselov._native, name)
        if not name.startswith("_") and callable(obj):
            found.append((f"veselov._native.{name}", obj))
    return found


def parameters(obj):
    """The names of the parameters a caller passes (no `self`), or None
    when Python knows no signature (a class inheriting a builtin's)."""
    try:
        signature = inspect.signature(obj)
    except (TypeError, ValueError):
        return None
    return [
        p.name
        for p in signature.parameters.values()
        if p.name != "self" and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)
    ]


def test_every_public_callable_and_class_has_a_numpy_style_docstring():
    api = dict(public_api())
    assert {
        "veselov.run",
        "veselov.ensemble",
        "veselov.verify",
        "veselov.read_dir",
        "veselov.toml_text",
        "veselov.models",
        "veselov.structures",
        "veselov.methods",
        "veselov.Result",
        "veselov.Result.keys",
        "veselov.Result.__getitem__",
        "veselov.ScenarioError",
        "veselov.VeselovError",
        "veselov.dask.ensemble",
        "veselov.resume",
        "veselov.Result.__iter__",
        "veselov.Result.__len__",
        "veselov._native.run_many",
        "veselov._native.verify",
    } <= set(api)
    assert set(veselov.__all__) <= {n.split(".")[1] for n in api}
    problems = []
    for name, obj in api.items():
        doc = inspect.getdoc(obj) if not inspect.isclass(obj) else inspect.cleandoc(obj.__doc__ or "")
        if not doc:
            problems.append(f"{name}: no docstring")
            continue
        lines = doc.splitlines()
        if len(lines) > 1 and lines[1].strip():
            problems.append(f"{name}: the summary is not one line followed by a blank line")
        found = sections(doc)
        params = parameters(obj)
        if inspect.isclass(obj):
            if "__init__" in vars(obj) and "Attributes" not in found:
                problems.append(f"{name}: a class with its own state and no Attributes section")
            if params is None or params:
                if "Parameters" not in found:
                    problems.append(f"{name}: no Parameters section for its constructor")
        else:
            if "Returns" not in found:
                problems.append(f"{name}: no Returns section")
            if params and "Parameters" not in found:
                problems.append(f"{name}: no Parameters section")
        for p in params or []:
            if not re.search(rf"^{re.escape(p)} :", found.get("Parameters", ""), re.M):
                problems.append(f"{name}: parameter `{p}` not documented")
    assert not problems, "\n".join(problems)


def test_docstrings_state_the_arrays_dtype_and_shape():
    for obj in (veselov.Result, veselov.Result.__getitem__, veselov.run, veselov.read_dir, veselov.verify):
        doc = inspect.getdoc(obj)
        assert "float64" in doc and "shape" in doc, obj
    assert "help(veselov.run)" in veselov.__doc__


@contextlib.contextmanager
def sigint_after(seconds):
    """Deliver SIGINT to this process after `seconds`, with Python's own
    Ctrl-C handler installed and the signal unblocked (whatever earlier
    tests' libraries left), as a user pressing Ctrl-C would."""
    handler = signal.signal(signal.SIGINT, signal.default_int_handler)
    blocked = signal.pthread_sigmask(signal.SIG_UNBLOCK, [signal.SIGINT])
    timer = threading.Timer(seconds, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        yield
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, handler)
        signal.pthread_sigmask(signal.SIG_SETMASK, blocked)


def harmonic(**keys):
    """A harmonic oscillator run by the midpoint rule: about 1e7 steps, a
    second or two, with the default keys."""
    scenario = {
        "model": {"name": "harmonic"},
        "method": {"name": "midpoint", "dt": 0.001},
        "time": {"t_end": 10000.0},
        "initial": {"q": [1.0], "p": [0.0]},
        "output": {"every": 100000},
    }
    text = veselov._native.merge(veselov.toml_text(scenario), veselov.toml_text(keys))[1]
    return text


def test_a_str_naming_an_existing_file_is_a_path_even_with_an_equals_sign(tmp_path, monkeypatch):
    sweep = tmp_path / "sweep" / "lr=0.1"
    sweep.mkdir(parents=True)
    (sweep / "scenario.toml").write_text(shortened("kepler.toml", tmp_path, **{"time.t_end": 1.0}).read_text())
    monkeypatch.chdir(tmp_path)
    r = veselov.run("sweep/lr=0.1/scenario.toml")
    assert r.status == "ok"
    assert r.summary["scenario"] == "sweep/lr=0.1/scenario.toml"
    r = veselov.run(str(sweep / "scenario.toml"))
    assert r.status == "ok"
    # A missing file named like one is reported as missing, not parsed as TOML.
    with pytest.raises(veselov.ScenarioError) as e:
        veselov.run("sweep/lr=0.2/scenario.toml")
    assert "sweep/lr=0.2/scenario.toml" in str(e.value) and "No such file" in str(e.value)
    # TOML text stays TOML text.
    text = 'model = { name = "harmonic" }\nmethod = { name = "midpoint", dt = 0.1 }\ntime = { t_end = 1.0 }'
    assert veselov.run(text).status == "ok"
    # One line with `=` naming no file is TOML text: the scenario's own error.
    with pytest.raises(veselov.ScenarioError) as e:
        veselov.run('model = { name = "harmonic" }')
    assert "No such file" not in str(e.value) and "method" in str(e.value)


def test_errors_name_the_arguments_of_python_not_the_command_line(tmp_path):
    out = tmp_path / "run"
    veselov.run(EXAMPLES / "harmonic.toml", out=out)
    with pytest.raises(veselov.VeselovError) as e:
        veselov.run(EXAMPLES / "harmonic.toml", out=out)
    message = str(e.value)
    assert "out=" in message and "force=True" in message and "--" not in message
    assert veselov.run(EXAMPLES / "harmonic.toml", out=out, force=True).status == "ok"

    veselov.ensemble(EXAMPLES / "harmonic.toml", [{}, {}], out=tmp_path / "members")
    with pytest.raises(veselov.VeselovError) as e:
        veselov.ensemble(EXAMPLES / "harmonic.toml", [{}, {}], out=tmp_path / "members")
    assert "force=True" in str(e.value) and "--" not in str(e.value) and e.value.member == 0
    again = veselov.ensemble(EXAMPLES / "harmonic.toml", [{}, {}], out=tmp_path / "members", force=True)
    assert [r.status for r in again] == ["ok", "ok"]

    with pytest.raises(veselov.ScenarioError) as e:
        veselov.verify(EXAMPLES / "harmonic.toml", [0.1, -0.05])
    assert e.value.key == "dt" and "--" not in str(e.value) and "`dt`" in str(e.value)

    with pytest.raises(veselov.ScenarioError) as e:
        veselov.run({"model": {"name": "harmonic"}, "method": {"name": "midpoint", "dt": 1e-12}, "time": {"t_end": 1e6}})
    assert "force_large=True" in str(e.value) and "--" not in str(e.value)

    # A run failing in a temporary directory does not point at it.
    failing = {
        "model": {"name": "custom", "coordinates": ["x"], "lagrangian": "0.5*x_dot^2 + 0.25*x^4"},
        "method": {"name": "midpoint", "dt": 0.01},
        "time": {"t_end": 5.0},
        "initial": {"q": [1.0], "p": [1.0]},
    }
    r = veselov.run(failing)
    assert r.status == "error" and r.message.startswith("run failed:")
    assert r.dir is None and "veselov-" not in r.message and "written to" not in r.message
    kept = veselov.run(failing, out=tmp_path / "failing")
    assert str(tmp_path / "failing") in kept.message and kept.dir == tmp_path / "failing"


def test_an_interrupted_run_keeps_its_checkpoint_and_resumes_bit_for_bit(tmp_path):
    text = harmonic()
    with sigint_after(0.3):
        r = veselov.run(text)
    assert r.status == "interrupted"
    # The temporary directory is kept, with its checkpoint, and named.
    assert r.dir is not None and (r.dir / "checkpoint.json").is_file()
    assert f"veselov.resume({str(r.dir)!r})" in r.message
    assert "--" not in r.message
    try:
        done = veselov.resume(r.dir)
        assert done.status == "ok" and done.dir == r.dir
        whole = veselov.run(text)
        assert whole.dir is None
        assert list(done) == list(whole)
        for name in whole:
            assert same_bits(done[name], whole[name]), name
    finally:
        shutil.rmtree(r.dir.parent, ignore_errors=True)

    # With out=, the message names the directory and how to continue.
    with sigint_after(0.3):
        r = veselov.run(text, out=tmp_path / "run")
    assert r.status == "interrupted" and r.dir == tmp_path / "run"
    assert f"veselov.resume({str(tmp_path / 'run')!r})" in r.message


def test_resume_extends_a_finished_run_from_its_recorded_scenario(tmp_path):
    short = veselov.run(harmonic(**{"time.t_end": 10.0}), out=tmp_path / "run")
    assert short.status == "ok"
    longer = veselov.resume(tmp_path / "run", overrides={"time.t_end": 20.0})
    alone = veselov.run(harmonic(**{"time.t_end": 20.0}))
    assert longer.status == "ok" and longer["t"][-1] == 20.0
    for name in alone:
        assert same_bits(longer[name], alone[name]), name
    # A key that may not change is refused, naming it.
    with pytest.raises(veselov.ScenarioError) as e:
        veselov.resume(tmp_path / "run", overrides={"method.dt": 0.002, "time.t_end": 30.0})
    assert e.value.key == "method.dt"
    # Nothing to resume from.
    (tmp_path / "empty").mkdir()
    with pytest.raises(veselov.VeselovError) as e:
        veselov.resume(tmp_path / "empty")
    assert "scenario=" in str(e.value)
    with pytest.raises(veselov.VeselovError) as e:
        veselov.resume(tmp_path / "empty", scenario=harmonic())
    assert "checkpoint" in str(e.value) and "--" not in str(e.value)


def test_resume_a_run_of_the_command_line(tmp_path):
    exe = command()
    if not exe.exists():
        pytest.skip(f"no command binary at {exe} (set VESELOV_BIN)")
    path = tmp_path / "harmonic.toml"
    path.write_text(harmonic(**{"time.t_end": 10.0}))
    subprocess.run([str(exe), "run", str(path), "--out", str(tmp_path / "cmd"), "--quiet"], check=True)
    path.write_text(harmonic(**{"time.t_end": 20.0}))
    r = veselov.resume(tmp_path / "cmd")
    assert r.status == "ok" and r["t"][-1] == 20.0


def test_result_is_a_mapping_of_its_arrays():
    kepler = veselov.run(EXAMPLES / "kepler.toml")
    rod = veselov.run(EXAMPLES / "rod_timoshenko.toml")
    field = veselov.run(EXAMPLES / "wave.toml")
    for r in (kepler, rod, field):
        assert isinstance(r, collections.abc.Mapping)
        names = list(r)
        assert len(r) == len(names) == len(set(names)) > 0
        assert list(r.keys()) == names
        assert all(isinstance(v, np.ndarray) and v.dtype == np.float64 for v in r.values())
        assert dict(r.items()).keys() == set(names)
        assert all(name in r for name in names)
        assert r.get("no such output") is None and r.get("no such output", 7) == 7
        assert 3 not in r and r.get(3) is None
        assert r.status == "ok" and r.summary["status"] == "ok"
        for stem, table in r.tables.items():
            for column, values in table.items():
                assert r[f"{stem}.{column}"] is values
                assert any(r[name] is values for name in names), (stem, column)
    assert "energy" in rod and rod["energy"] is rod.tables["energy"]["energy"]
    assert "P_x" in rod and "energy.t" in rod and "t" not in rod
    assert rod["rotation_matrices"].shape == rod.arrays["frames"].shape[:2] + (3, 3)
    assert same_bits(rod["rotation_matrices"].reshape(rod.arrays["frames"].shape), rod.arrays["frames"])
    assert "energy" in field and "snapshots" in field
    with pytest.raises(KeyError):
        rod["t"]


def test_rigid_body_rotations_as_matrices(tmp_path):
    r = veselov.run(shortened("rigid_body.toml", tmp_path, **{"time.t_end": 2.0}))
    rotations = r["rotation_matrices"]
    n = len(r["t"])
    assert rotations.shape == (n, 3, 3) and rotations.dtype == np.float64 and rotations.flags.c_contiguous
    for i in range(3):
        for j in range(3):
            assert same_bits(rotations[:, i, j], r[f"R{i}{j}"])
    assert np.allclose(rotations @ rotations.transpose(0, 2, 1), np.eye(3), atol=1e-10)
    assert "rotation_matrices" in list(r)
    npy_only = veselov.run(shortened("rigid_body.toml", tmp_path, **{"time.t_end": 2.0, "output.formats": ["npy"]}))
    assert same_bits(npy_only["rotation_matrices"], rotations)


def test_ensemble_keeps_the_results_of_the_members_that_ran():
    base = EXAMPLES / "harmonic.toml"
    with pytest.raises(veselov.ScenarioError) as e:
        veselov.ensemble(base, [{}, {"method.dt": 0.0}, {"initial.q": [0.5]}])
    assert e.value.member == 1 and e.value.key == "method.dt" and "member 1" in str(e.value)
    results = e.value.results
    assert len(results) == 3 and results[1] is e.value
    assert results[0].status == results[2].status == "ok"
    assert results[2]["q"][0] == 0.5

    kept = veselov.ensemble(base, [{}, {"method.dt": 0.0}, {"initial.q": None}, {"initial.q": [0.5]}], on_error="keep")
    assert isinstance(kept[0], veselov.Result) and isinstance(kept[3], veselov.Result)
    assert isinstance(kept[1], veselov.ScenarioError) and kept[1].member == 1 and kept[1].key == "method.dt"
    assert isinstance(kept[2], veselov.ScenarioError) and kept[2].member == 2 and "override 2" in str(kept[2])
    assert same_bits(kept[3]["q"], results[2]["q"])
    with pytest.raises(ValueError):
        veselov.ensemble(base, [{}], on_error="ignore")


def test_dask_errors_name_the_member_in_the_whole_ensemble_and_its_file():
    distributed = pytest.importorskip("distributed")
    members = [{"time.steps": 100}] * 5
    members[3] = {"method.dt": -1.0}
    path = EXAMPLES / "harmonic.toml"
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            with pytest.raises(veselov.ScenarioError) as e:
                veselov.dask.ensemble(client, path, members, batch=2)
            kept = veselov.dask.ensemble(client, path, members, batch=2, on_error="keep")
    assert e.value.member == 3 and "member 3" in str(e.value) and str(path) in str(e.value)
    assert e.value.key == "method.dt"
    assert [type(r).__name__ for r in e.value.results] == ["Result"] * 3 + ["ScenarioError", "Result"]
    assert isinstance(kept[3], veselov.ScenarioError) and kept[3].member == 3 and str(path) in str(kept[3])
    local = veselov.ensemble(path, members, on_error="keep")
    for a, b in zip(local, kept):
        if isinstance(a, veselov.Result):
            assert same_bits(a["q"], b["q"])
        else:
            assert str(a) == str(b) and a.member == b.member


def test_verify_takes_one_step_or_many():
    one = veselov.verify(EXAMPLES / "harmonic.toml", 0.1)
    assert one["dt"].shape == (1,)
    many = veselov.verify(EXAMPLES / "harmonic.toml", np.array([0.1, 0.05]))
    assert same_bits(many["dt"][:1], one["dt"])
    assert veselov.verify(EXAMPLES / "harmonic.toml", (0.1, 0.05))["dt"].shape == (2,)
    for bad in ("0.1", [0.1, "0.05"], [True]):
        with pytest.raises(TypeError) as e:
            veselov.verify(EXAMPLES / "harmonic.toml", bad)
        assert "dt: expected a number or a sequence of numbers" in str(e.value)
    for missing in ([], None):
        with pytest.raises(veselov.ScenarioError) as e:
            veselov.verify(EXAMPLES / "harmonic.toml", missing)
        assert e.value.key == "dt"


def test_verify_refines_a_lattice_field_with_the_options_of_the_command(tmp_path):
    wave = (EXAMPLES / "wave.toml").read_text().replace("t_end = 50.0", "t_end = 2.0")
    study = veselov.verify(wave, refine=3, out=tmp_path / "v")
    assert study.summary["observable"] == "field"
    assert study.summary["error_estimate"] == "richardson"
    assert abs(study.summary["order_fitted"] - 2.0) < 0.3
    assert study["dx"].shape == (4,)
    energy = veselov.verify(wave, nodes=[200, 400, 800], observable="energy")
    assert energy.summary["observable"] == "energy"
    for options, key in (({}, "refine"), ({"refine": 2, "observable": "tip-displacement"}, "observable")):
        with pytest.raises(veselov.ScenarioError) as e:
            veselov.verify(wave, **options)
        assert e.value.key == key and "--" not in str(e.value)


def test_ctrl_c_stops_verify_and_is_raised(tmp_path):
    steps = list(np.linspace(0.0012, 0.001, 40))  # ~0.2 s each
    out = tmp_path / "study"
    with sigint_after(0.3):
        with pytest.raises(KeyboardInterrupt):
            veselov.verify(harmonic(), steps, out=out)
    assert not (out / "convergence.csv").exists()  # stopped before the end


def test_read_dir_reads_a_convergence_study(tmp_path):
    study = veselov.verify(EXAMPLES / "harmonic.toml", [0.1, 0.05], out=tmp_path / "study")
    read = veselov.read_dir(tmp_path / "study")
    assert read.status == study.status == "ok"
    assert read.summary["order_claimed"] == study.summary["order_claimed"]
    for name in study:
        assert same_bits(read[name], study[name])
