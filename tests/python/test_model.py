"""Models built in Python: the same model as the file, the same verbs as the C++ builder."""

import importlib.util

import numpy as np
import pytest

import stiffmsa
from conftest import EXAMPLES, ROOT


def load_example(name):
    spec = importlib.util.spec_from_file_location(name, ROOT / "examples" / "python" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_arm_built_in_python_equals_the_file():
    built = load_example("planar_2r_arm").planar_2r_arm()
    read = stiffmsa.load_model(EXAMPLES / "planar-2r.yaml")
    assert built.to_dict() == read.to_dict()
    assert built == read
    assert built.source_file == "" and read.source_file.endswith("planar-2r.yaml")
    assert stiffmsa.solve(built).to_json() == stiffmsa.solve(read).to_json()


def test_a_changed_number_makes_another_model():
    built = load_example("planar_2r_arm").planar_2r_arm()
    read = stiffmsa.load_model(EXAMPLES / "planar-2r.yaml")
    built.add_point("spare", [1, 2, 3])
    assert built != read


def test_to_dict_holds_every_kind_of_entity():
    model = stiffmsa.Model("kinds")
    model.add_point("a", np.array([0.0, 0.0, 0.0]))
    model.add_point("b", (1.0, 0.0, 0.0))
    model.add_point("c", [1.0, 0.0, 0.0])
    # A free-free stiffness: a spring of 1e6 on the end `to`'s motion relative to `from`'s carried
    # rigidly along d = b - a (paper eq. (2)), so that rigid motions cost nothing.
    d = np.array([1.0, 0.0, 0.0])
    skew = np.array([[0, -d[2], d[1]], [d[2], 0, -d[0]], [-d[1], d[0], 0]])
    transport = np.block([[np.eye(3), skew.T], [np.zeros((3, 3)), np.eye(3)]])
    relative = np.hstack([-transport, np.eye(6)])
    stiffness = 1e6 * relative.T @ relative
    model.add_matrix_link("cad", "a", "b", stiffness, "local", zref=[0, 1, 0])
    model.add_compliance_link("bushing", "b", "c", np.eye(6) * 1e-7)
    model.add_joint("weld", "b", ["cad", "bushing"])
    model.add_support("ground", "a", "cad", stiffmsa.Connection(stiffmsa.Kinematics.universal([1, 0, 0], [0, 1, 0]),
                                                                stiffness=np.diag([1e3, 2e3]), actuated=True))
    model.add_load("c", "bushing", [1, 2, 3, 4, 5, 6])
    model.add_end_effector("tool", "c", link="bushing")
    d = model.to_dict()
    assert d["links"]["cad"]["type"] == "matrix" and d["links"]["cad"]["frame"] == "local"
    assert d["links"]["cad"]["zref"] == [0.0, 1.0, 0.0]
    assert d["links"]["cad"]["K"] == stiffness.tolist()
    assert d["links"]["bushing"]["type"] == "compliance" and d["links"]["bushing"]["frame"] == "global"
    assert d["joints"]["weld"] == {"at": "b", "links": ["cad", "bushing"], "type": "rigid", "stiffness": None,
                                   "preload": None, "actuated": False}
    assert d["supports"]["ground"]["axes"] == ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
    assert d["supports"]["ground"]["stiffness"] == [[1e3, 0.0], [0.0, 2e3]]
    assert d["supports"]["ground"]["links"] == ["cad"]
    assert d["loads"] == [{"at": "c", "link": "bushing", "wrench": [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]}]
    assert d["end_effectors"] == {"tool": {"at": "c", "link": "bushing"}}
    assert repr(model) == ("<stiffmsa.Model 'kinds': 3 points, 2 links, 1 joint, 1 support, 1 load, "
                           "1 end effector>")
    size = stiffmsa.check(model)
    assert size.unknowns > 0 and size.unknowns == size.equations


def test_add_load_takes_the_c_plus_plus_order_too():
    first, second = stiffmsa.Model(), stiffmsa.Model()
    first.add_load("tip", None, [1, 0, 0, 0, 0, 0])
    second.add_load("tip", [1, 0, 0, 0, 0, 0])
    assert first.to_dict()["loads"] == second.to_dict()["loads"]


def test_copy_is_independent():
    model = stiffmsa.load_model(EXAMPLES / "planar-2r.yaml")
    copy = model.copy()
    copy.name = "other"
    assert model.name == "planar-2r"


def test_sections_and_materials_keep_their_numbers():
    section = stiffmsa.Section.tube(0.05, 0.005, Asy=1e-4)
    assert (section.shape, section.D, section.t, section.Asy, section.Asz) == ("tube", 0.05, 0.005, 1e-4, None)
    material = stiffmsa.Material(2.1e11, G=8e10)
    assert (material.E, material.nu, material.G) == (2.1e11, None, 8e10)
    assert stiffmsa.Kinematics.planar([0, 0, 1]).free_direction_count == 3
    with pytest.raises(stiffmsa.UsageError):
        stiffmsa.Kinematics.custom([[1, 0, 0]])


def test_cantilever_built_in_code_matches_its_closed_forms():
    E, nu, D, L = 2.1e11, 0.3, 0.05, 1.2
    model = stiffmsa.Model("rod")
    model.add_point("root", [0, 0, 0])
    model.add_point("tip", [L, 0, 0])
    model.add_beam("rod", "root", "tip", stiffmsa.Material(E=E, nu=nu), stiffmsa.Section.circle(D))
    model.add_support("clamp", "root", ["rod"])
    model.add_load("tip", "rod", [0, -100, 0, 0, 0, 0])
    model.add_end_effector("tool", "tip", "rod")
    tool = stiffmsa.solve(model).end_effectors["tool"]
    A, I = np.pi * D**2 / 4, np.pi * D**4 / 64
    G = E / (2 * (1 + nu))
    closed = {(0, 0): L / (E * A), (1, 1): L**3 / (3 * E * I), (3, 3): L / (G * 2 * I), (5, 5): L / (E * I),
              (1, 5): L**2 / (2 * E * I)}
    for (row, col), value in closed.items():
        assert tool.compliance[row, col] == pytest.approx(value, rel=1e-9), (row, col)
    assert tool.deflection[1] == pytest.approx(-100 * L**3 / (3 * E * I), rel=1e-9)


def test_named_materials_sections_and_connection_factories_build_the_same_arm():
    built = load_example("planar_2r_arm").planar_2r_arm()
    named = stiffmsa.Model("planar-2r")
    named.add_material("aluminium", stiffmsa.Material(E=7.0e10, nu=0.33))
    named.add_section("upper_box", stiffmsa.Section.rect_tube(0.06, 0.08, 0.004))
    named.add_section("fore_box", stiffmsa.Section.rect_tube(0.05, 0.06, 0.003))
    assert sorted(named.sections) == ["fore_box", "upper_box"] and named.materials["aluminium"].E == 7.0e10
    for name, position in built.to_dict()["points"].items():
        named.add_point(name, position)
    named.add_rigid_link("pedestal", "floor", "shoulder")
    named.add_beam("upper_arm", "shoulder", "elbow", "aluminium", "upper_box")
    named.add_beam("forearm", "elbow", "tip", "aluminium", "fore_box")
    turning = stiffmsa.Kinematics.revolute([0, 0, 1])
    named.add_joint("shoulder_joint", "shoulder", ["pedestal", "upper_arm"], stiffmsa.Connection.elastic(turning, 2.0e5))
    named.add_joint("elbow_joint", "elbow", ["upper_arm", "forearm"], stiffmsa.Connection.elastic(turning, 1.0e5))
    named.add_support("base", "floor", [], stiffmsa.Connection.rigid())
    named.add_load("tip", [50, -200, 0, 0, 0, 0])
    named.add_end_effector("tool", "tip")
    assert stiffmsa.solve(named).to_json() == stiffmsa.solve(built).to_json()
    with pytest.raises(stiffmsa.UsageError, match="there is no material 'aluminum'; did you mean 'aluminium'"):
        named.add_beam("spare", "elbow", "tip", "aluminum", "fore_box")


def test_connection_factories():
    hinge = stiffmsa.Kinematics.revolute([0, 0, 1])
    motor = stiffmsa.Connection.actuator(hinge)
    assert motor.actuated and motor.stiffness is None
    drive = stiffmsa.Connection.actuator(hinge, 3e4).preloaded(2.5)
    assert drive.actuated and drive.stiffness.tolist() == [[3e4]] and drive.preload.tolist() == [2.5]
    assert not stiffmsa.Connection.passive(hinge).actuated
    assert stiffmsa.Connection.rigid().kinematics.free_direction_count == 0


def test_results_by_name():
    result = stiffmsa.solve(load_example("planar_2r_arm").planar_2r_arm())
    assert np.array_equal(result.end_effector("tool").compliance, result.end_effectors["tool"].compliance)
    assert result.joint("elbow_joint").actuated is False
    assert result.report.usable and result.report.solver == "tree"
    with pytest.raises(stiffmsa.UsageError, match="there is no joint 'elbow_jiont'; did you mean 'elbow_joint'"):
        result.joint("elbow_jiont")
