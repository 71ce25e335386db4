"""Errors are exceptions carrying what the stiffmsa command prints: every defect of an invalid
model with its file, line, column and key, and the free motions of a mechanism."""

import re

import pytest

import stiffmsa
from conftest import EXAMPLES, ROOT, run_cli

INVALID = ROOT / "tests" / "invalid"


def expectations():
    """{file: [(key path, "line:column")]} from tests/invalid/expectations.txt."""
    expected = {}
    for line in (INVALID / "expectations.txt").read_text().splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        file, key_path, position, *_ = [field.strip() for field in line.split("|")]
        expected.setdefault(file, []).append((key_path, position))
    return expected


EXPECTED = expectations()


def test_the_corpus_is_there():
    assert len(EXPECTED) > 40


@pytest.mark.parametrize("file", sorted(EXPECTED), ids=str)
def test_invalid_model_raises_input_error_with_its_diagnostics(file, cli):
    path = INVALID / file
    with pytest.raises(stiffmsa.InputError) as raised:
        stiffmsa.load_model(path)
    diagnostics = raised.value.diagnostics
    found = [(d.key_path or "-", f"{d.line}:{d.column}" if d.line else "-") for d in diagnostics]
    assert sorted(found) == sorted(EXPECTED[file])
    for d in diagnostics:
        assert d.file == str(path)
        assert d.message
    # The command prints the same diagnostics, one per line, naming its flags where the library
    # names its options.
    stderr = run_cli(cli, "solve", path, check=False).stderr
    assert [line for line in stderr.splitlines() if line.startswith("stiffmsa: error: ")] == [
        f"stiffmsa: error: {with_flag_hints(str(d))}" for d in diagnostics]


# The library's options and the command's flags for them, as the command prints them.
FLAG_OF_OPTION = {
    "(LoadLimits::max_file_bytes)": "with --max-file-size BYTES",
    "(LoadLimits::max_nesting_depth)": "with --max-depth N",
    "(LoadLimits::max_entities)": "with --max-entities N",
    "SolveOptions::accept_idle_motions": "--accept-idle-motions",
}


def with_flag_hints(message):
    for option, flag in FLAG_OF_OPTION.items():
        message = message.replace(option, flag)
    return message


def test_errors_are_stiffmsa_errors():
    for error in (stiffmsa.InputError, stiffmsa.SingularModelError, stiffmsa.IoError, stiffmsa.UsageError):
        assert issubclass(error, stiffmsa.Error)
    assert issubclass(stiffmsa.IoError, OSError)
    assert issubclass(stiffmsa.UsageError, ValueError)


def test_missing_file_is_an_io_error(tmp_path):
    with pytest.raises(stiffmsa.IoError, match="nothing.yaml"):
        stiffmsa.load_model(tmp_path / "nothing.yaml")


def two_link_mechanism(stiffness=None):
    """Two rigid links hinged together and to the ground, loaded at the tip: free to fold
    unless the elbow has a stiffness."""
    model = stiffmsa.Model("folding")
    model.add_point("ground", [0, 0, 0])
    model.add_point("elbow", [1, 0, 0])
    model.add_point("tip", [2, 0.5, 0])
    model.add_rigid_link("upper", "ground", "elbow")
    model.add_rigid_link("lower", "elbow", "tip")
    model.add_support("base", "ground", ["upper"], stiffmsa.Connection(stiffmsa.Kinematics.revolute([0, 0, 1]),
                                                                       stiffness=1e4))
    model.add_joint("hinge", "elbow", ["upper", "lower"],
                    stiffmsa.Connection(stiffmsa.Kinematics.revolute([0, 0, 1]), stiffness=stiffness))
    model.add_load("tip", [0, -10, 0, 0, 0, 0])
    model.add_end_effector("tool", "tip")
    return model


def test_mechanism_raises_singular_model_error_naming_the_free_motion(tmp_path, cli):
    with pytest.raises(stiffmsa.SingularModelError) as raised:
        stiffmsa.solve(two_link_mechanism())
    error = raised.value
    assert error.cause == "free_motion"
    assert error.details and any("hinge" in detail for detail in error.details)
    assert str(error).splitlines()[1:] == [f"  {detail}" for detail in error.details]
    # With a spring at the hinge it is a structure.
    stiffness = stiffmsa.solve(two_link_mechanism(stiffness=2e3)).end_effectors["tool"].stiffness
    assert stiffness is None or stiffness.shape == (6, 6)


def test_mechanism_file_gives_the_command_s_message(tmp_path, cli):
    mechanism = tmp_path / "mechanism.yaml"
    text = (EXAMPLES / "planar-2r.yaml").read_text().replace(", stiffness: 1.0e5}", "}")
    mechanism.write_text(text)
    with pytest.raises(stiffmsa.SingularModelError) as raised:
        stiffmsa.solve(stiffmsa.load_model(mechanism))
    stderr = run_cli(cli, "solve", mechanism, check=False).stderr
    assert stderr.splitlines()[0] == f"stiffmsa: error: {raised.value.summary}"
    assert stderr.splitlines()[1:] == [f"  {detail}" for detail in raised.value.details]


def test_model_built_in_code_with_a_defect_names_the_key():
    model = two_link_mechanism(stiffness=2e3)
    model.add_joint("J9", "elbow", ["upper", "nowhere"])
    with pytest.raises(stiffmsa.InputError) as raised:
        stiffmsa.solve(model)
    diagnostics = raised.value.diagnostics
    assert [d.key_path for d in diagnostics] == ["joints.J9.links[0]", "joints.J9.links[1]"]
    assert all(d.file is None and d.line is None and d.column is None for d in diagnostics)
    assert "already in joint 'hinge'" in diagnostics[0].message
    assert diagnostics[1].message == "no link named 'nowhere'; links are: upper, lower"
    assert str(diagnostics[1]) == "joints.J9.links[1]: no link named 'nowhere'; links are: upper, lower"


def test_bad_arguments_are_usage_errors_that_say_what_is_wrong():
    model = stiffmsa.Model()
    with pytest.raises(stiffmsa.UsageError, match=re.escape("point 'p': position: expected 3 numbers, got an array of shape (2,)")):
        model.add_point("p", [1.0, 2.0])
    with pytest.raises(stiffmsa.UsageError, match="solver 'lu': expected one of auto, sparse_lu, umfpack, klu"):
        stiffmsa.solve(two_link_mechanism(2e3), solver="lu")
    with pytest.raises(stiffmsa.UsageError, match="Connection stiffness: expected a 1×1 matrix"):
        stiffmsa.Connection(stiffmsa.Kinematics.revolute([0, 0, 1]), stiffness=[[1.0, 2.0]])
    with pytest.raises(stiffmsa.UsageError, match="no parameter 'z'"):
        stiffmsa.load_model(EXAMPLES / "planar-3rpr-parametric.yaml", z=1.0)


def test_a_name_that_is_not_there_is_a_name_error_with_its_kind_name_and_suggestion():
    assert issubclass(stiffmsa.NameError, stiffmsa.UsageError)
    assert issubclass(stiffmsa.NameError, LookupError)
    assert "NameError" not in stiffmsa.__all__  # a star-import keeps Python's own NameError
    result = stiffmsa.solve(two_link_mechanism(2e3))
    with pytest.raises(stiffmsa.NameError, match="there is no joint 'hinje'; did you mean 'hinge'") as raised:
        result.joint("hinje")
    assert (raised.value.kind, raised.value.name, raised.value.suggestion) == ("joint", "hinje", "hinge")
    with pytest.raises(stiffmsa.NameError) as raised:
        result.end_effector("gripper")
    assert (raised.value.kind, raised.value.name, raised.value.suggestion) == ("end effector", "gripper", None)
    with pytest.raises(stiffmsa.NameError) as raised:
        result.load_case_result("machining")
    assert (raised.value.kind, raised.value.name) == ("load case", "machining")

    # A family's parameter: the message names the family and its file, wherever it is looked up.
    path = EXAMPLES / "planar-3rpr-parametric.yaml"
    family = stiffmsa.load_family(path)
    for call in (lambda: family.build(phii=0.1), lambda: family.solve(phii=0.1),
                 lambda: family.with_defaults(phii=0.1), lambda: family.sweep(grid={"phii": (0.0, 0.1, 2)}),
                 lambda: stiffmsa.load_family(path, phii=0.1), lambda: stiffmsa.load_model(path, phii=0.1)):
        with pytest.raises(stiffmsa.NameError) as raised:
            call()
        assert str(raised.value) == (f"the model 'planar-3rpr-parametric' ({path}) has no parameter 'phii'; "
                                     "did you mean 'phi'?")
        assert (raised.value.kind, raised.value.name, raised.value.suggestion) == ("parameter", "phii", "phi")
    # Still the UsageError it was.
    with pytest.raises(stiffmsa.UsageError, match="no parameter 'z'"):
        family.build(z=1.0)
    # A family of a function has no file.
    of_function = stiffmsa.ModelFamily.from_function(lambda reach: two_link_mechanism(2e3), {"reach": 1.0},
                                                     name="arm")
    with pytest.raises(stiffmsa.NameError) as raised:
        of_function.build(height=0.2)
    assert str(raised.value) == "the model 'arm' has no parameter 'height'; its parameters are: reach"
    assert raised.value.suggestion is None
