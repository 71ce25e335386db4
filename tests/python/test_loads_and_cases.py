"""Issue 22's inputs from Python: densities, settlements, loads along links, gravity, load cases
and the analysis mode, built with the same verbs as a model file's keys; the results' new
fields and solve's new options."""

import re

import numpy as np
import pytest

import stiffmsa
from conftest import run_cli

FRAME_FILE = """format: stiffmsa/1
name: frame
analysis: {mode: loaded, load_steps: 8}
gravity: [0, 0, -9.81]
points: {O: [0, 0, 0], A: [1, 0, 0], E: [2, 0, 0]}
links:
  beam1: {type: beam, from: O, to: A, material: {E: 2.1e11, nu: 0.3, density: 7850}, section: {shape: circle, D: 0.05}}
  beam2: {type: beam, from: A, to: E, material: {E: 2.1e11, nu: 0.3, density: 7850}, section: {shape: circle, D: 0.05}}
joints: {J: {type: rigid, at: A, links: [beam1, beam2]}}
supports:
  base: {type: rigid, at: O, displacement: [0, 0, -0.001, 0, 0, 0]}
loads:
  - {link: beam1, distributed: [0, 0, -500]}
  - {at: E, wrench: [0, 0, -1000, 0, 0, 0]}
  - {link: beam2, force: [0, 0, -200], moment: [0, 10, 0], position: 0.3}
load_cases:
  machining: [{at: E, wrench: [0, 0, -1000, 0, 0, 0]}, {link: beam2, distributed: {from: [0, 0, -100], to: [0, 0, -300]}}]
  heavy: {loads: [], gravity: [0, -9.81, 0]}
end_effectors: {tip: {at: E}}
"""


def frame_built_in_python():
    model = stiffmsa.Model("frame")
    model.mode = "loaded"
    model.load_steps = 8
    model.gravity = [0, 0, -9.81]
    for name, position in (("O", [0, 0, 0]), ("A", [1, 0, 0]), ("E", [2, 0, 0])):
        model.add_point(name, position)
    steel = stiffmsa.Material(2.1e11, nu=0.3, density=7850)
    model.add_beam("beam1", "O", "A", steel, stiffmsa.Section.circle(0.05))
    model.add_beam("beam2", "A", "E", steel, stiffmsa.Section.circle(0.05))
    model.add_joint("J", "A", ["beam1", "beam2"])
    model.add_support("base", "O", displacement=[0, 0, -0.001, 0, 0, 0])
    model.add_load("E", [0, 0, -1000, 0, 0, 0])
    model.add_link_load("beam1", stiffmsa.DistributedLinkLoad([0, 0, -500]))
    model.add_link_load("beam2", stiffmsa.PointLinkLoad([0, 0, -200], [0, 10, 0], position=0.3))
    machining = stiffmsa.LoadCase("machining")
    machining.add_load("E", [0, 0, -1000, 0, 0, 0])
    machining.add_link_load("beam2", stiffmsa.DistributedLinkLoad([0, 0, -100], [0, 0, -300]))
    model.add_load_case(machining)
    model.add_load_case(stiffmsa.LoadCase("heavy", gravity=[0, -9.81, 0]))
    model.add_end_effector("tip", "E")
    return model


def test_a_model_built_in_python_equals_the_file(tmp_path):
    path = tmp_path / "frame.yaml"
    path.write_text(FRAME_FILE)
    read = stiffmsa.load_model(path)
    built = frame_built_in_python()
    assert built.to_dict() == read.to_dict()
    assert built == read
    d = read.to_dict()
    assert d["analysis"] == {"mode": "loaded", "load_steps": 8}
    assert d["gravity"] == [0.0, 0.0, -9.81]
    assert d["links"]["beam1"]["material"]["density"] == 7850.0
    assert d["supports"]["base"]["displacement"] == [0.0, 0.0, -0.001, 0.0, 0.0, 0.0]
    assert d["loads"][1] == {"link": "beam1", "distributed": {"from": [0.0, 0.0, -500.0], "to": [0.0, 0.0, -500.0]}}
    assert d["loads"][2] == {"link": "beam2", "force": [0.0, 0.0, -200.0], "moment": [0.0, 10.0, 0.0],
                             "position": 0.3}
    assert d["load_cases"]["heavy"] == {"loads": [], "gravity": [0.0, -9.81, 0.0]}
    assert list(d["load_cases"]) == ["machining", "heavy"]
    # A change of an issue-22 number makes another model.
    built.gravity = [0, 0, -9.8]
    assert built != read


def test_the_models_loads_along_links_and_cases_read_back():
    model = frame_built_in_python()
    assert model.mode == stiffmsa.AnalysisMode.loaded and model.load_steps == 8
    np.testing.assert_array_equal(model.gravity, [0, 0, -9.81])
    first, second = model.link_loads
    assert first.link == "beam1" and isinstance(first.load, stiffmsa.DistributedLinkLoad)
    np.testing.assert_array_equal(first.load.from_, first.load.to)
    assert isinstance(second.load, stiffmsa.PointLinkLoad) and second.load.position == 0.3
    assert second.load.force.dtype == np.float64
    machining, heavy = model.load_cases
    assert machining.name == "machining" and len(machining.loads) == 1 and len(machining.link_loads) == 1
    assert machining.loads[0].at == "E" and machining.loads[0].link is None
    np.testing.assert_array_equal(machining.loads[0].wrench, [0, 0, -1000, 0, 0, 0])
    assert machining.gravity is None
    np.testing.assert_array_equal(heavy.gravity, [0, -9.81, 0])
    assert repr(model) == ("<stiffmsa.Model 'frame': 3 points, 2 links, 1 joint, 1 support, 3 loads, "
                           "2 load cases, 1 end effector>")
    assert repr(heavy) == "<stiffmsa.LoadCase 'heavy': 0 loads, gravity>"
    model.gravity = None
    model.load_steps = None
    assert model.gravity is None and model.load_steps is None


def test_new_values_are_plain_classes():
    q = stiffmsa.DistributedLinkLoad([0, 0, -1], to=np.array([0.0, 0.0, -3.0]))
    np.testing.assert_array_equal(q.to, [0, 0, -3])
    q.from_ = (1, 2, 3)
    assert repr(q) == "DistributedLinkLoad(from_=[1.0, 2.0, 3.0], to=[0.0, 0.0, -3.0])"
    p = stiffmsa.PointLinkLoad([1, 0, 0], position=0.5)
    np.testing.assert_array_equal(p.moment, [0, 0, 0])
    assert repr(p) == "PointLinkLoad(force=[1.0, 0.0, 0.0], moment=[0.0, 0.0, 0.0], position=0.5)"
    load = stiffmsa.LinkLoad("beam", p)
    load.load = q
    assert isinstance(load.load, stiffmsa.DistributedLinkLoad)
    assert stiffmsa.Material(2.1e11, 0.3).density is None
    assert repr(stiffmsa.Material(2.1e11, 0.3, density=7850)) == "Material(E=2.1e+11, nu=0.3, density=7850)"
    with pytest.raises(stiffmsa.UsageError, match=re.escape("DistributedLinkLoad from_: expected 3 numbers")):
        stiffmsa.DistributedLinkLoad([0, 0])
    with pytest.raises(stiffmsa.UsageError, match="expected a DistributedLinkLoad or a PointLinkLoad"):
        stiffmsa.Model().add_link_load("beam", [0, 0, 1])
    with pytest.raises(stiffmsa.UsageError, match="support 's': displacement: expected 6 numbers"):
        stiffmsa.Model().add_support("s", "O", displacement=[0, 0, 1])
    with pytest.raises(stiffmsa.UsageError, match=re.escape("analysis mode 'nonlinear': expected \"linear\"")):
        stiffmsa.Model().mode = "nonlinear"


def test_validation_reports_issue_22_defects():
    model = frame_built_in_python()
    model.add_link_load("beam3", stiffmsa.PointLinkLoad([0, 0, 1], position=1.5))
    with pytest.raises(stiffmsa.InputError) as error:
        stiffmsa.check(model)
    by_key = {d.key_path: d.message for d in error.value.diagnostics}
    assert "no link named 'beam3'; did you mean 'beam1'?" in by_key["link_loads[2].link"]
    assert by_key["link_loads[2].position"].startswith("position is a fraction of the link's length")
    weightless = stiffmsa.Model()
    weightless.add_point("O", [0, 0, 0])
    weightless.add_point("A", [1, 0, 0])
    weightless.add_beam("L", "O", "A", stiffmsa.Material(2.1e11, 0.3), stiffmsa.Section.circle(0.05))
    weightless.add_support("S", "O")
    weightless.gravity = [0, 0, -9.81]
    with pytest.raises(stiffmsa.InputError, match="gravity is given but no beam's material has a density"):
        stiffmsa.check(weightless)


def test_solve_options_take_the_mode_and_the_critical_load():
    options = stiffmsa.SolveOptions(mode="loaded", critical_load=True)
    assert options.mode == stiffmsa.AnalysisMode.loaded and options.critical_load is True
    assert stiffmsa.SolveOptions().mode is None and stiffmsa.SolveOptions().critical_load is None
    assert stiffmsa.SolveOptions(critical_load=False).critical_load is False
    assert stiffmsa.SolveOptions(critical_load=np.bool_(False)).critical_load is False
    assert stiffmsa.SolveOptions(mode=stiffmsa.AnalysisMode.linear).mode == stiffmsa.AnalysisMode.linear
    with pytest.raises(stiffmsa.UsageError, match=re.escape("mode 'nonlinear': expected \"linear\", \"loaded\"")):
        stiffmsa.SolveOptions(mode="nonlinear")


def without_critical_load_lines(result):
    return [line for line in result.to_json().splitlines() if '"critical_load_' not in line]


def every_case(result):
    return [result, *result.load_cases.values(), *([result.linear] if result.linear else [])]


def test_critical_load_none_is_the_contract_true_always_false_never(tmp_path):
    """``critical_load``: None (the default) finds the factor where the result's contract has it
    (here load cases, gravity and the loaded mode), as before; False never, every other number of
    the result the same to the last bit; True always, also where the contract has none."""
    path = tmp_path / "frame.yaml"
    path.write_text(FRAME_FILE)
    model = stiffmsa.load_model(path)
    usual = stiffmsa.solve(model)
    assert all(case.critical_load is not None for case in [usual, *usual.load_cases.values()])
    assert stiffmsa.solve(model, critical_load=None).to_json() == usual.to_json()
    assert stiffmsa.solve(model, critical_load=True).to_json() == usual.to_json()
    for never in (stiffmsa.solve(model, critical_load=False), stiffmsa.solve(model, critical_load=np.bool_(False)),
                  stiffmsa.load_family(path).solve(critical_load=False)):
        assert all(case.critical_load is None for case in every_case(never))
        assert '"critical_load_' not in never.to_json()
        assert without_critical_load_lines(never) == without_critical_load_lines(usual)

    # A column under a plain load in the linear mode: the contract has no factor.
    column = stiffmsa.Model("column")
    column.add_point("O", [0, 0, 0])
    column.add_point("E", [0, 0, 1])
    column.add_beam("L", "O", "E", stiffmsa.Material(2.1e11, 0.3), stiffmsa.Section.circle(0.05))
    column.add_support("S", "O")
    column.add_load("E", [0, 0, -1000, 0, 0, 0])
    column.add_end_effector("tip", "E")
    linear = stiffmsa.solve(column)
    assert linear.critical_load is None
    assert stiffmsa.solve(column, critical_load=False).to_json() == linear.to_json()
    asked = stiffmsa.solve(column, critical_load=True)
    assert asked.critical_load is not None and asked.critical_load.factor > 1
    assert without_critical_load_lines(asked) == without_critical_load_lines(linear)


@pytest.mark.parametrize("value", [1, 0, "never", 1.0, [False]], ids=repr)
def test_critical_load_of_another_type_is_a_type_error_naming_it(value):
    expected = re.escape("critical_load: expected None (where the result's contract has it), True (always) or "
                         f"False (never), got {value!r} ({type(value).__name__})")
    with pytest.raises(TypeError, match=expected):
        stiffmsa.SolveOptions(critical_load=value)
    with pytest.raises(TypeError, match="critical_load"):
        stiffmsa.solve(stiffmsa.Model("empty"), critical_load=value)


def test_a_linear_result_of_the_unnamed_case_has_the_new_fields():
    model = stiffmsa.Model("cantilever")
    model.add_point("O", [0, 0, 0])
    model.add_point("E", [1, 0, 0])
    model.add_beam("L", "O", "E", stiffmsa.Material(2.1e11, 0.3), stiffmsa.Section.circle(0.05))
    model.add_rigid_link("R", "E", "T")
    model.add_point("T", [1.5, 0, 0])
    model.add_support("S", "O")
    model.add_load("T", [0, 0, -100, 0, 0, 0])
    model.add_end_effector("tip", "T")
    result = stiffmsa.solve(model, mode="linear")
    assert result.load_case == ""
    assert result.analysis.mode == stiffmsa.AnalysisMode.linear
    assert result.critical_load is None
    assert result.load_cases == {}
    assert result.linear is None
    assert result.links["R"].internal_forces == []
    for station in result.links["L"].internal_forces:  # filled where the analysis gives them
        assert 0 <= station.position <= 1 and station.forces.shape == (6,)
    with pytest.raises(stiffmsa.UsageError, match="there is no load case 'machining'"):
        result.load_case_result("machining")


def test_family_solves_and_sweeps_take_the_mode(tmp_path):
    path = tmp_path / "frame.yaml"
    path.write_text(FRAME_FILE.replace("analysis: {mode: loaded, load_steps: 8}\n", ""))
    family = stiffmsa.load_family(path)
    result = family.solve(mode="linear")
    assert result.analysis.mode == stiffmsa.AnalysisMode.linear
    with pytest.raises(stiffmsa.UsageError, match="mode 'sideways'"):
        family.solve(mode="sideways")
    with pytest.raises(stiffmsa.UsageError, match="mode 'sideways'"):
        family.sweep(poses={}, mode="sideways")


def test_the_loaded_mode_takes_loads_along_links_and_gravity(tmp_path, cli):
    """The frame's loads along its beams and its own weight, in the loaded mode (theory.md
    §15.9): solved in every case, the reactions a little off the linear ones (the loads ride
    with the deformed beams), the internal forces at the equilibrium; the command agrees."""
    path = tmp_path / "frame.yaml"
    path.write_text(FRAME_FILE)
    result = stiffmsa.solve(stiffmsa.load_model(path))
    assert result.analysis.mode == stiffmsa.AnalysisMode.loaded
    assert result.linear.analysis.mode == stiffmsa.AnalysisMode.linear
    for case in [result, *result.load_cases.values()]:
        loaded, linear = case.supports["base"].reaction, case.linear.supports["base"].reaction
        assert np.linalg.norm(loaded - linear) < 1e-2 * np.linalg.norm(linear)
        beam = case.links["beam1"]
        assert len(beam.internal_forces) >= 11
        # From minus the from end's wrench (in the beam's co-rotated axes) to the to end's.
        assert np.isclose(np.linalg.norm(beam.internal_forces[0].forces), np.linalg.norm(beam.from_.wrench))
        assert np.isclose(np.linalg.norm(beam.internal_forces[-1].forces), np.linalg.norm(beam.to.wrench))
    out = tmp_path / "frame.json"
    run_cli(cli, "solve", path, "--json", out)
    assert '"mode": "loaded"' in out.read_text()


def test_a_column_beyond_its_critical_load_raises_no_equilibrium_with_its_load_factor():
    """A clamped-free steel column of 4 beams under 30 kN against Euler's 13 818 N: the loaded
    mode's path stops near 13 818/30 000 = 0.4606 of the loads, as the command reports."""
    model = stiffmsa.Model("column")
    for i in range(5):
        model.add_point(f"p{i}", [0, 0, 0.25 * i])
    steel = stiffmsa.Material(2.1e11, nu=0.3)
    section = stiffmsa.Section.rect(0.02, 0.04)
    for i in range(4):
        model.add_beam(f"c{i}", f"p{i}", f"p{i + 1}", steel, section)
    model.add_support("base", "p0")
    model.add_load("p4", [0, 0, -30000, 0, 0, 0])
    model.add_end_effector("top", "p4")
    euler = np.pi**2 * 2.1e11 * (0.04 * 0.02**3 / 12) / (4 * 1.0**2)
    with pytest.raises(stiffmsa.NoEquilibriumError) as raised:
        stiffmsa.solve(model, mode="loaded")
    assert isinstance(raised.value, stiffmsa.Error)
    # The path is bracketed to 1e-4 of the loads; 4 elements put the critical load 6e-5 above
    # Euler's.
    assert abs(raised.value.load_factor - euler / 30000) < 2e-4
    assert "critical point" in str(raised.value)
