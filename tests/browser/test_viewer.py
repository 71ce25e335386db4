#!/usr/bin/env python3
"""The viewer in a real browser: `stiffmsa view` pages of the examples (serial arms, parallel
robots) and of a building frame opened in headless Chromium, each checked for no error, no
request outside the page, a drawing that is not blank and that changes with the deformation
scale; a model whose names are HTML shows them as text and runs nothing; the sweep map draws.

    test_viewer.py --cli build/stiffmsa --source . [--screenshots DIR]

Exits 77 (ctest's "skipped") where Chromium is not installed."""
import argparse
import os
import pathlib
import subprocess
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import chromium_pipe  # noqa: E402
import png_pixels  # noqa: E402

SKIPPED = 77
WIDTH, HEIGHT = 1000, 700
PANEL_WIDTH = 310  # the panel on the left; the drawing is right of it
BACKGROUND = (0xf4, 0xf5, 0xf7)

# An end effector on a rod, with names a browser would run as HTML if the page let it.
HOSTILE_MODEL = """format: stiffmsa/1
name: "</script><script>window.stiffmsaInjected = 2</script>"
points:
  O: [0, 0, 0]
  "<b>E</b>": [1, 0, 0]
links:
  "<img src=x onerror=window.stiffmsaInjected=1>":
    type: beam
    from: O
    to: "<b>E</b>"
    material: {E: 2.1e11, nu: 0.3}
    section: {shape: circle, D: 0.05}
supports:
  "S&amp;1": {type: rigid, at: O}
loads:
  - {at: "<b>E</b>", wrench: [0, -100, 0, 0, 0, 0]}
end_effectors:
  "<svg onload=window.stiffmsaInjected=3>": {at: "<b>E</b>"}
"""

# Every kind of link and most joint kinds, held so loosely that it is a mechanism: the page
# still draws the model, without a deformed shape, and says why.
KINDS_MODEL = """format: stiffmsa/1
name: every kind
points:
  O: [0, 0, 0]
  A: [0.5, 0, 0]
  B: [0.5, 0.4, 0]
  C: [0.5, 0.4, 0.3]
  D: [0.9, 0.4, 0.3]
links:
  beam: {type: beam, from: O, to: A, material: {E: 2.1e11, nu: 0.3}, section: {shape: rect, b: 0.04, h: 0.06}}
  casting: {type: compliance, from: A, to: B, C: [[1e-7,0,0,0,0,0],[0,1e-7,0,0,0,0],[0,0,1e-7,0,0,0],[0,0,0,1e-5,0,0],[0,0,0,0,1e-5,0],[0,0,0,0,0,1e-5]]}
  bar: {type: rigid, from: B, to: C}
  tool: {type: beam, from: C, to: D, material: {E: 7e10, nu: 0.33}, section: {shape: tube, D: 0.03, t: 0.003}}
joints:
  U: {type: universal, at: A, links: [beam, casting], axes: [[0, 0, 1], [0, 1, 0]], stiffness: [[1e4, 0], [0, 1e4]]}
  Z: {type: cylindrical, at: B, links: [casting, bar], axis: [0, 0, 1]}
  P: {type: planar, at: C, links: [bar, tool], normal: [0, 0, 1]}
supports:
  ground: {type: spherical, at: O}
loads:
  - {at: D, wrench: [0, 0, -50, 0, 0, 0]}
end_effectors:
  tip: {at: D}
"""

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)
    return condition


def drawn_pixels(image, region_left=PANEL_WIDTH):
    """Pixels right of the panel that are not the background, and their distinct colours."""
    width, height, _, _ = image
    drawn, colours = 0, set()
    for y in range(0, height, 2):
        for x in range(region_left, width, 2):
            pixel = png_pixels.rgb(image, x, y)
            if max(abs(a - b) for a, b in zip(pixel, BACKGROUND)) > 8:
                drawn += 1
                colours.add(pixel)
    return drawn / (((width - region_left) // 2) * (height // 2)), len(colours)


def differing_fraction(first, second):
    width, height, _, _ = first
    differ = sum(1 for y in range(0, height, 2) for x in range(PANEL_WIDTH, width, 2)
                 if png_pixels.rgb(first, x, y) != png_pixels.rgb(second, x, y))
    return differ / (((width - PANEL_WIDTH) // 2) * (height // 2))


def open_page(browser, html, fragment=""):
    url = pathlib.Path(html).resolve().as_uri() + fragment
    page = chromium_pipe.Page(browser, url, WIDTH, HEIGHT)
    status = page.evaluate("document.getElementById('stiffmsa-status').textContent")
    check(status == "ready", f"{html}{fragment}: the page did not finish drawing (status {status!r})")
    page.next_frames()
    return page


def page_errors(page, label):
    errors = page.errors()
    shown = page.evaluate("document.getElementById('stiffmsa-errors').textContent")
    check(not errors and not shown, f"{label}: errors in the page: {errors} {shown!r}")
    outside = [u for u in page.requests() if not u.startswith(("file:", "data:", "about:"))]
    check(not outside, f"{label}: the page asked for {outside}")


def view(cli, model, html, expected_exit=0):
    run = subprocess.run([cli, "view", str(model), "-o", str(html)], capture_output=True, text=True)
    check(run.returncode == expected_exit, f"stiffmsa view {model}: exit {run.returncode}: {run.stderr}")
    return html.exists()


def check_model_page(browser, cli, model, folder, screenshots, shot_name, loaded=True, expected_exit=0):
    html = folder / (pathlib.Path(model).stem + ".html")
    if not view(cli, model, html, expected_exit):
        return
    page = open_page(browser, html)
    page_errors(page, str(model))
    shot = page.screenshot()
    page.close()
    image = png_pixels.decode(shot)
    drawn, colours = drawn_pixels(image)
    print(f"{pathlib.Path(model).name}: {drawn:.1%} of the drawing area drawn, {colours} colours")
    check(drawn > 0.01 and colours > 20, f"{model}: the drawing looks blank ({drawn:.2%} drawn, {colours} colours)")
    if screenshots and shot_name:
        (screenshots / shot_name).write_bytes(shot)
    if loaded:
        # Undeformed (scale 0) against the automatic magnification: the deformed shape moves.
        flat_page = open_page(browser, html, "#scale=0")
        flat = png_pixels.decode(flat_page.screenshot())
        flat_page.close()
        changed = differing_fraction(image, flat)
        print(f"{pathlib.Path(model).name}: {changed:.2%} of the pixels change with the scale")
        check(changed > 0.002, f"{model}: the drawing does not change with the deformation scale ({changed:.3%})")


def check_stiffness_ellipsoids(browser, html):
    """The ellipsoids switched to stiffness, with every name labelled: drawn without error."""
    page = open_page(browser, html, "#ellipsoid=stiffness&names=1")
    page_errors(page, "stiffness ellipsoids")
    panel = page.evaluate("document.getElementById('effectors').textContent")
    check("translational stiffness (N/m)" in panel, f"the panel does not list principal stiffnesses: {panel!r}")
    labels = page.evaluate("document.querySelectorAll('#labels .label').length")
    check(labels > 10, f"names on: only {labels} labels")
    page.close()


def check_hostile_names(browser, cli, folder):
    model = folder / "hostile.yaml"
    model.write_text(HOSTILE_MODEL)
    html = folder / "hostile.html"
    if not view(cli, model, html):
        return
    page = open_page(browser, html, "#names=1")
    page_errors(page, "hostile names")
    check(page.evaluate("window.stiffmsaInjected") is None, "a name from the model ran as script")
    check(page.evaluate("document.querySelectorAll('img, svg, [onerror], [onload]').length") == 0, "a name from the model became an element")
    labels = page.evaluate("document.getElementById('labels').textContent")
    check("<img src=x onerror=window.stiffmsaInjected=1>" in labels, f"the link's name is not shown as text: {labels!r}")
    # The mouse on the end effector: its name in the tooltip, as text.
    where = page.evaluate("stiffmsaScreenOf('<b>E</b>')")
    page.send("Input.dispatchMouseEvent", {"type": "mouseMoved", "x": where["x"], "y": where["y"]})
    page.next_frames()
    tooltip = page.evaluate("document.getElementById('tooltip').hidden ? '' : document.getElementById('tooltip').textContent")
    check(tooltip.startswith("end effector <svg onload=window.stiffmsaInjected=3>\nat <b>E</b>"),
          f"hovering the end effector does not name it: {tooltip!r}")
    check(page.evaluate("window.stiffmsaInjected") is None, "hovering ran a name from the model")
    title = page.evaluate("document.getElementById('title').textContent")
    check(title == "</script><script>window.stiffmsaInjected = 2</script>", f"the model's name is not the title: {title!r}")
    page.close()


def check_sweep_map(browser, cli, source, folder, screenshots):
    csv = folder / "sweep.csv"
    run = subprocess.run([cli, "sweep", str(source / "examples/planar-3rpr-parametric.yaml"), "--grid", "x=-0.1:0.1:21",
                          "--grid", "y=-0.1:0.1:21", "--csv", str(csv), "--full", "--view", "--quiet"],
                         capture_output=True, text=True)
    if not check(run.returncode == 0, f"stiffmsa sweep --view: exit {run.returncode}: {run.stderr}"):
        return
    html = csv.with_suffix(".html")
    page = open_page(browser, html)
    # The mouse over the map, as a user moves it: the panel shows the pose under it.
    page.send("Input.dispatchMouseEvent", {"type": "mouseMoved", "x": 600, "y": 200})
    page.next_frames()
    pose = page.evaluate("document.querySelector('#pose td') && document.querySelector('#pose td').textContent")
    check(pose not in (None, "1"), f"the sweep map does not follow the mouse (pose {pose!r})")
    page_errors(page, "sweep map")
    rows = page.evaluate("document.querySelectorAll('#pose tr').length")
    check(rows > 5, f"the sweep map shows no row of values for a pose ({rows} rows)")
    check(page.evaluate("!document.getElementById('ellipses').hidden"), "the sweep map shows no ellipses with --full")
    shot = page.screenshot()
    page.close()
    drawn, colours = drawn_pixels(png_pixels.decode(shot))
    check(drawn > 0.2 and colours > 20, f"the sweep map looks blank ({drawn:.2%} drawn, {colours} colours)")
    if screenshots:
        (screenshots / "viewer-sweep-map.png").write_bytes(shot)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cli", required=True)
    parser.add_argument("--source", required=True, type=pathlib.Path)
    parser.add_argument("--screenshots", type=pathlib.Path, help="keep one screenshot per example class here")
    args = parser.parse_args()
    executable = chromium_pipe.find_chromium()
    if not executable:
        print("skipped: Chromium is not installed (scripts/install-deps.sh viewer installs it)")
        return SKIPPED
    if args.screenshots:
        args.screenshots.mkdir(parents=True, exist_ok=True)
    examples = args.source / "examples"
    with tempfile.TemporaryDirectory(prefix="stiffmsa-viewer-") as temporary, chromium_pipe.Chromium(executable) as browser:
        folder = pathlib.Path(temporary)
        frame = folder / "frame-5x5x10.yaml"
        frame.write_text(subprocess.run([sys.executable, str(args.source / "bench/make_models.py"), "frame", "5", "5", "10"],
                                        capture_output=True, text=True, check=True).stdout)
        pages = [(examples / "industrial-6axis.yaml", "viewer-serial-arm.png", True),
                 (examples / "gough-stewart-6ups.yaml", "viewer-parallel-robot.png", True),
                 (frame, "viewer-frame.png", True),
                 (examples / "planar-3rpr.yaml", None, True),
                 (examples / "tripteron.yaml", None, True),
                 (examples / "planar-2r.yaml", None, True),
                 (examples / "cantilever.yaml", None, True)]
        for model, shot_name, loaded in pages:
            check_model_page(browser, args.cli, model, folder, args.screenshots, shot_name, loaded)
        check_stiffness_ellipsoids(browser, folder / "industrial-6axis.html")
        kinds = folder / "every-kind.yaml"
        kinds.write_text(KINDS_MODEL)
        check_model_page(browser, args.cli, kinds, folder, args.screenshots, "viewer-every-kind.png", loaded=False,
                         expected_exit=1)
        check_hostile_names(browser, args.cli, folder)
        check_sweep_map(browser, args.cli, args.source, folder, args.screenshots)
    if failures:
        print(f"{len(failures)} failure(s)")
        return 1
    print("all viewer checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
