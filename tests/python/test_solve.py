"""Every example model solved from Python gives the stiffmsa command's result file to the last
bit, and the result's numpy arrays are those numbers."""

import json

import numpy as np
import pytest

import stiffmsa
from conftest import EXAMPLES, run_cli

EXAMPLE_MODELS = sorted(EXAMPLES.glob("*.yaml"))


def test_there_are_examples():
    assert len(EXAMPLE_MODELS) >= 8


def same_array(array, listed):
    """A result's array against the result file's list (None for null), bit for bit."""
    if listed is None:
        return array is None
    expected = np.array(listed, dtype=np.float64)
    return (array is not None and array.dtype == np.float64 and array.shape == expected.shape
            and np.array_equal(array, expected))


@pytest.mark.parametrize("path", EXAMPLE_MODELS, ids=lambda p: p.name)
def test_example_equals_cli_result_file(path, cli, tmp_path):
    cli_file = tmp_path / "cli.json"
    run_cli(cli, "solve", path, "--json", cli_file)
    result = stiffmsa.solve(stiffmsa.load_model(path))
    assert result.to_json() == cli_file.read_text()
    expected = json.loads(cli_file.read_text())
    assert result.to_dict() == expected
    python_file = tmp_path / "python.json"
    result.write_json(python_file)
    assert python_file.read_bytes() == cli_file.read_bytes()

    # The same numbers through the attributes.
    assert list(result.end_effectors) == list(expected["end_effectors"])
    for name, listed in expected["end_effectors"].items():
        effector = result.end_effectors[name]
        assert (effector.point, effector.link) == (listed["point"], listed["link"])
        for quantity in ("compliance", "stiffness", "deflection"):
            assert same_array(getattr(effector, quantity), listed[quantity]), (name, quantity)
    assert list(result.links) == list(expected["link_ends"])
    for name, listed in expected["link_ends"].items():
        link = result.links[name]
        for end, attribute in (("from", "from_"), ("to", "to")):
            for quantity in ("deflection", "wrench"):
                assert same_array(getattr(getattr(link, attribute), quantity), listed[end][quantity])
                assert same_array(getattr(link[end], quantity), listed[end][quantity])
    assert list(result.joints) == list(expected["joints"])
    for name, listed in expected["joints"].items():
        joint = result.joints[name]
        assert same_array(joint.relative_deflection, listed["relative_deflection"])
        assert same_array(joint.wrench, listed["wrench"])
        assert same_array(joint.effort, listed.get("effort"))
    assert list(result.supports) == list(expected["supports"])
    for name, listed in expected["supports"].items():
        assert same_array(result.supports[name].reaction, listed["reaction"])
    report = expected["report"]
    assert result.report.solver == report["solver"]
    assert result.report.relative_residual == report["relative_residual"]
    assert result.report.equilibrium_error == report["equilibrium_error"]
    assert result.report.warnings == report["warnings"]
    assert result.report.notes == report["notes"]
    assert (result.system.unknowns, result.system.equations, result.system.nonzeros) == (
        expected["system"]["unknowns"], expected["system"]["equations"], expected["system"]["nonzeros"])


@pytest.mark.parametrize("solver", ["sparse_lu", "klu"])
def test_solver_option_as_on_the_command_line(solver, cli, tmp_path):
    path = EXAMPLES / "planar-2r.yaml"
    cli_file = tmp_path / "cli.json"
    run_cli(cli, "solve", path, "--json", cli_file, "--solver", solver)
    result = stiffmsa.solve(stiffmsa.load_model(path), solver=solver)
    assert result.report.solver == solver
    assert result.to_json() == cli_file.read_text()


def test_load_model_values_replace_parameters_as_set_does(cli, tmp_path):
    path = EXAMPLES / "planar-3rpr-parametric.yaml"
    cli_file = tmp_path / "cli.json"
    run_cli(cli, "solve", path, "--json", cli_file, "--set", "x=0.41", "--set", "phi=-0.05")
    model = stiffmsa.load_model(path, x=0.41, phi=-0.05)
    assert stiffmsa.solve(model).to_json() == cli_file.read_text()
    # and differs from the defaults' result
    assert stiffmsa.solve(stiffmsa.load_model(path)).to_json() != cli_file.read_text()


def test_family_solve_is_the_member_solved(cli, tmp_path):
    path = EXAMPLES / "tripteron-parametric.yaml"
    cli_file = tmp_path / "cli.json"
    run_cli(cli, "solve", path, "--json", cli_file, "--set", "px=0.3", "--set", "pz=0.33")
    family = stiffmsa.load_family(path)
    assert family.solve(px=0.3, pz=0.33).to_json() == cli_file.read_text()
    assert family.solve({"px": 0.3}, pz=0.33).to_json() == cli_file.read_text()
    assert stiffmsa.solve(family.build(px=0.3, pz=0.33)).to_json() == cli_file.read_text()


def test_arrays_are_float64_six_by_six_and_read_only():
    result = stiffmsa.solve(stiffmsa.load_model(EXAMPLES / "planar-2r.yaml"))
    tool = result.end_effectors["tool"]
    assert tool.compliance.shape == (6, 6) and tool.compliance.dtype == np.float64
    assert tool.stiffness.shape == (6, 6) and tool.deflection.shape == (6,)
    # The stiffness is the compliance's inverse where both are given.
    assert np.allclose(tool.stiffness @ tool.compliance, np.eye(6), atol=1e-9)
    with pytest.raises(ValueError):
        tool.compliance[0, 0] = 1.0


def test_repr_shows_the_essentials():
    model = stiffmsa.load_model(EXAMPLES / "planar-2r.yaml")
    assert repr(model) == ("<stiffmsa.Model 'planar-2r': 4 points, 3 links, 2 joints, 1 support, 1 load, "
                           "1 end effector>")
    text = repr(stiffmsa.solve(model))
    assert text.startswith("<stiffmsa.Result of 'planar-2r' (solver tree): end effectors tool (k_trans_min ")


def test_pathlib_and_str_paths_give_the_same_model():
    path = EXAMPLES / "planar-2r.yaml"
    assert stiffmsa.load_model(path) == stiffmsa.load_model(str(path))
