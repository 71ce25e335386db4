"""Sweeps from Python: the stiffmsa command's CSV byte for byte, columns keyed as its header,
families from Python functions, and the GIL released while the C++ threads solve."""

import csv
import io
import json
import math
import threading
import time

import numpy as np
import pytest

import stiffmsa
from conftest import EXAMPLES, run_cli

RPR = EXAMPLES / "planar-3rpr-parametric.yaml"
TRIPTERON = EXAMPLES / "tripteron-parametric.yaml"
RPR_GRID = {"x": (0.3, 0.6, 7), "y": (0.2, 0.4, 5)}
# Reaches beyond the legs' reach at large px and py, so that some poses fail and leave empty
# cells, with messages that hold commas (quoted in the CSV).
TRIPTERON_GRID = {"px": (0.1, 0.55, 7), "py": (0.1, 0.5, 5)}


def grid_options(grid):
    options = []
    for name, (start, stop, count) in grid.items():
        options += ["--grid", f"{name}={start!r}:{stop!r}:{count}"]
    return options


def cli_sweep(cli, tmp_path, model, *options):
    out = tmp_path / "cli.csv"
    run_cli(cli, "sweep", model, "--csv", out, "--quiet", *options)
    return out


def parsed_columns(text):
    """The CSV's columns as the contract states them: numbers, NaN for an empty cell."""
    rows = list(csv.reader(io.StringIO(text)))
    header, body = rows[0], rows[1:]
    columns = {}
    for k, name in enumerate(header):
        cells = [row[k] for row in body]
        columns[name] = cells if name in ("status", "message") else [float(c) if c else math.nan for c in cells]
    return columns


def assert_columns_match_csv(result, text):
    expected = parsed_columns(text)
    assert list(result.columns) == list(expected)
    for name, values in expected.items():
        column = result.columns[name]
        assert len(column) == len(result)
        if name in ("status", "message"):
            assert list(column) == values
        else:
            assert column.dtype == np.float64
            assert np.array_equal(column, np.array(values), equal_nan=True), name


def test_grid_sweep_equals_the_command_s_csv(cli, tmp_path):
    cli_csv = cli_sweep(cli, tmp_path, TRIPTERON, *grid_options(TRIPTERON_GRID), "--threads", "2")
    result = stiffmsa.load_family(TRIPTERON).sweep(grid=TRIPTERON_GRID, threads=2)
    assert result.to_csv() == cli_csv.read_text()
    python_csv = tmp_path / "python.csv"
    result.write_csv(python_csv)
    assert python_csv.read_bytes() == cli_csv.read_bytes()
    assert_columns_match_csv(result, cli_csv.read_text())
    statuses = set(result.status)
    assert "ok" in statuses and statuses != {"ok"}, statuses  # the grid has failed poses too
    assert np.isnan(result.columns["platform.k_trans_min"][result.status != "ok"]).all()
    assert any("," in message for message in result.message)
    assert len(result) == 35 and result.parameters == ["px", "py"] and result.units == ["m", "m"]
    assert result.grid == TRIPTERON_GRID
    assert np.array_equal(result.poses["px"], result.columns["px"])


def test_worst_poses_are_the_summary_s(cli, tmp_path):
    cli_sweep(cli, tmp_path, TRIPTERON, *grid_options(TRIPTERON_GRID))
    cli_summary = json.loads((tmp_path / "cli.summary.json").read_text())
    result = stiffmsa.load_family(TRIPTERON).sweep(grid=TRIPTERON_GRID)
    assert result.worst == cli_summary["worst"]
    summary = result.summary
    for key in ("format", "model", "poses", "parameters", "status", "worst"):
        assert summary[key] == cli_summary[key], key
    worst = result.worst["platform.k_trans_min"]
    column = result.columns["platform.k_trans_min"]
    assert worst["value"] == np.nanmin(column) and worst["pose"] == int(np.nanargmin(column))
    summary_file = tmp_path / "python.summary.json"
    result.write_summary(summary_file, csv="cli.csv")
    written = json.loads(summary_file.read_text())
    assert written["csv"] == "cli.csv" and written["worst"] == cli_summary["worst"]


def test_full_sweep_of_listed_poses_equals_the_command_s(cli, tmp_path):
    poses = {"px": np.array([0.30, 0.32, 0.34, 0.36]), "pz": [0.28, 0.30, 0.31, 0.33]}
    pose_file = tmp_path / "poses.csv"
    pose_file.write_text("px,pz\n" + "".join(f"{x!r},{z!r}\n" for x, z in zip(poses["px"], poses["pz"])))
    cli_csv = cli_sweep(cli, tmp_path, TRIPTERON, "--poses", pose_file, "--full", "--set", "L2=0.26")
    family = stiffmsa.load_family(TRIPTERON, L2=0.26)
    result = family.sweep(poses=poses, full=True)
    assert result.to_csv() == cli_csv.read_text()
    assert_columns_match_csv(result, cli_csv.read_text())
    assert "platform.C11" in result.columns and "platform.K66" in result.columns
    # with_defaults is load_family's keyword values, later
    assert stiffmsa.load_family(TRIPTERON).with_defaults(L2=0.26).sweep(poses=poses, full=True).to_csv() == (
        result.to_csv())


def test_to_pandas_has_every_column():
    pandas = pytest.importorskip("pandas")
    result = stiffmsa.load_family(RPR).sweep(grid={"x": (0.4, 0.5, 3)})
    frame = result.to_pandas()
    assert isinstance(frame, pandas.DataFrame)
    assert list(frame.columns) == list(result.columns) and len(frame) == 3
    assert np.array_equal(frame["platform.k_trans_min"].to_numpy(), result.columns["platform.k_trans_min"])


def rpr_member(x, y):
    return stiffmsa.load_model(RPR, x=x, y=y)


def test_family_of_a_python_function_equals_the_file_s():
    from_function = stiffmsa.ModelFamily.from_function(rpr_member, {"x": 0.46, "y": 0.33}, units={"x": "m", "y": "m"})
    assert [p.name for p in from_function.parameters] == ["x", "y"]
    assert from_function.name == "rpr_member"
    grid = {"x": (0.4, 0.5, 4), "y": (0.3, 0.36, 3)}
    by_python = from_function.sweep(grid=grid, threads=2)
    by_file = stiffmsa.load_family(RPR).sweep(grid=grid)
    assert by_python.to_csv() == by_file.to_csv()
    assert from_function.solve(x=0.41).to_json() == stiffmsa.solve(rpr_member(0.41, 0.33)).to_json()


def test_a_python_function_s_exception_fails_the_pose_and_is_raised_by_build():
    def member(x, y):
        if x >= 0.45:
            raise ValueError("x is too far")
        return rpr_member(x, y)

    family = stiffmsa.ModelFamily.from_function(member, {"x": 0.4, "y": 0.33})
    result = family.sweep(grid={"x": (0.4, 0.5, 3)})
    assert list(result.status) == ["ok", "invalid", "invalid"]
    assert "ValueError: x is too far" in result.message[1]
    with pytest.raises(ValueError, match="x is too far"):
        family.build(x=0.5)
    # At the defaults, which fix the sweep's topology, the exception is the sweep's.
    with pytest.raises(ValueError, match="x is too far"):
        family.with_defaults(x=0.5).sweep(grid={"y": (0.3, 0.4, 2)})
    not_a_model = stiffmsa.ModelFamily.from_function(lambda x: 1.0, {"x": 0.0})
    with pytest.raises(stiffmsa.UsageError, match=r"<lambda>\(x=0.0\) returned 1.0, not a stiffmsa.Model"):
        not_a_model.sweep(grid={"x": (0, 1, 2)})


def test_progress_is_reported_to_the_end():
    calls = []
    stiffmsa.load_family(RPR).sweep(grid={"x": (0.4, 0.5, 20)}, progress=lambda done, total: calls.append((done, total)))
    assert calls and calls[-1] == (20, 20)


def test_sweep_arguments_are_checked():
    family = stiffmsa.load_family(RPR)
    with pytest.raises(stiffmsa.UsageError, match="either as grid"):
        family.sweep()
    with pytest.raises(stiffmsa.UsageError, match="'z'"):
        family.sweep(grid={"z": (0, 1, 2)})
    with pytest.raises(stiffmsa.UsageError, match="one value per pose"):
        family.sweep(poses={"x": [0.4, 0.5], "y": [0.3]})
    with pytest.raises(stiffmsa.UsageError, match="threads"):
        family.sweep(grid={"x": (0.4, 0.5, 2)}, threads=0)


def test_the_gil_is_released_while_the_sweep_runs():
    family = stiffmsa.load_family(RPR)
    stamps = []
    started = threading.Event()
    stop = threading.Event()

    def tick():
        started.set()
        while not stop.is_set():
            stamps.append(time.monotonic())

    ticker = threading.Thread(target=tick)
    ticker.start()
    started.wait()
    # One thread and no progress callback: the sweep never hands the GIL over by itself.
    begin = time.monotonic()
    result = family.sweep(grid={"x": (0.35, 0.55, 80), "y": (0.25, 0.40, 80)}, threads=1)
    end = time.monotonic()
    stop.set()
    ticker.join()
    assert len(result) == 6400 and end - begin > 0.1
    # Held by the sweep, the GIL could pass to the ticker only before the sweep took it (within
    # a switch interval, 5 ms, of its start) or after it returned: ticks well inside the sweep
    # show that the Python thread ran meanwhile.
    margin = 0.02
    inside = [t for t in stamps if begin + margin < t < end - margin]
    assert len(inside) > 100, (len(inside), end - begin)
