"""The Python examples run as a user runs them, and the plots they write are pictures."""

import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT

EXAMPLES = ROOT / "examples" / "python"


def run_example(name, *args, cwd):
    completed = subprocess.run([sys.executable, str(EXAMPLES / name), *map(str, args)], cwd=cwd,
                               capture_output=True, text=True)
    assert completed.returncode == 0, completed.stderr
    return completed.stdout


def assert_is_a_picture(path):
    """A PNG whose pixels are not one colour: a drawn plot, not an empty canvas."""
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    image = pytest.importorskip("matplotlib.image").imread(path)
    height, width = image.shape[:2]
    assert width > 400 and height > 300
    colours = np.unique(image.reshape(-1, image.shape[-1]), axis=0)
    assert len(colours) > 50, len(colours)
    # Something is drawn besides the white background: lines, labels, a map.
    assert np.mean(np.all(image[..., :3] > 0.99, axis=-1)) < 0.97


def test_planar_2r_arm_prints_the_file_s_stiffness(tmp_path):
    import stiffmsa

    output = run_example("planar_2r_arm.py", cwd=tmp_path)
    assert output.startswith("planar-2r: end effector 'tool' at point 'tip' (solver tree)")
    stiffness = stiffmsa.solve(stiffmsa.load_model(ROOT / "examples" / "planar-2r.yaml")).end_effectors["tool"].stiffness
    with np.printoptions(precision=4, linewidth=110):
        assert str(stiffness) in output


def test_rpr_stiffness_map_draws_a_map(tmp_path):
    out = tmp_path / "map.png"
    output = run_example("rpr_stiffness_map.py", out, cwd=tmp_path)
    assert f"wrote {out}" in output
    assert_is_a_picture(out)


def test_tripteron_designs_draws_both(tmp_path):
    out = tmp_path / "designs.png"
    output = run_example("tripteron_designs.py", out, cwd=tmp_path)
    assert output.count("poses reachable, softest") == 2
    assert_is_a_picture(out)
